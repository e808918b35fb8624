#pragma once
// Component: tape perception. On every new camera frame: find the tape and the end mark
// (LineDetector), check that the camera still sees something (FrameHealth), and publish what was
// seen, in the robot frame, with the odometry pose it was seen from.
#include <cstdint>

#include "firmware/core/FaultSink.hpp"
#include "firmware/core/SampleReader.hpp"
#include "firmware/core/Status.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/health/SensorHealth.hpp"
#include "firmware/msg/ActuatorCommand.hpp"
#include "firmware/msg/LineObservation.hpp"
#include "firmware/msg/OdometryMsg.hpp"
#include "firmware/msg/SensorFrame.hpp"
#include "firmware/perception/CameraModel.hpp"
#include "firmware/perception/LineDetector.hpp"

namespace carril::fw {

struct LinePerceptionConfig {
  CameraMount camera;
  double rate_hz = 30.0;  // camera frame rate [Hz]
  LineDetectorConfig detector;
  FrameHealthConfig health;

  Status validate() const;
  bool operator==(const LinePerceptionConfig&) const = default;
};

struct LinePerceptionTelemetry {
  std::uint64_t frames_processed = 0;
  int frame_spread = 0;  // colour spread of the last frame (0: one flat colour)
};

class LinePerception {
 public:
  LinePerception(const LinePerceptionConfig& cfg, const Topic<SensorFrame>& frame,
                 const Topic<OdometryMsg>& odom, Topic<LineObservation>& out, FaultSink& faults);

  // Task: processes the newest frame if it is new.
  void run();
  const CameraModel& camera() const { return cam_; }
  LinePerceptionTelemetry telemetry() const;

 private:
  LinePerceptionConfig cfg_;
  CameraModel cam_;
  LineDetector detector_;
  FrameHealth health_;
  const Topic<SensorFrame>& frame_;
  const Topic<OdometryMsg>& odom_;
  Topic<LineObservation>& out_;
  FaultSink& faults_;
  SampleReader<hal::CameraFrame> frames_;
  std::uint64_t processed_ = 0;
};

}  // namespace carril::fw
