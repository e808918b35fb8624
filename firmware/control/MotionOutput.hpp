#pragma once
// Component: the last stage before the drives. Takes the mission runner's motion request, makes
// it feasible (MotionLimiter: speed, acceleration and wheel-speed limits) and publishes the
// actuator command; zero while the drives are not all enabled, and a quick stop once a fault has
// latched, whatever was requested.
#include <cstdint>
#include "firmware/control/MotionLimiter.hpp"
#include "firmware/msg/MotionRequest.hpp"

#include "firmware/core/FaultSink.hpp"
#include "firmware/core/Topic.hpp"
#include "firmware/msg/ActuatorCommand.hpp"
#include "firmware/msg/SensorFrame.hpp"

namespace carril::fw {

struct MotionOutputTelemetry {
  std::uint64_t commands = 0;          // actuator commands published
  std::uint64_t drives_not_ready = 0;  // of them zero because a drive was not enabled
  std::uint64_t quick_stops = 0;       // of them quick stops (a fault had latched)
};

class MotionOutput {
 public:
  MotionOutput(const MotionLimits& limits, const DriveKinematics& kin, double period_s,
               const Topic<SensorFrame>& frame, const Topic<MotionRequest>& request,
               Topic<ActuatorCommand>& out, const FaultSink& faults);

  // Task: one actuator command.
  void run();
  const MotionOutputTelemetry& telemetry() const { return tel_; }

 private:
  const DriveKinematics& kin_;
  MotionLimiter limiter_;
  const Topic<SensorFrame>& frame_;
  const Topic<MotionRequest>& request_;
  Topic<ActuatorCommand>& out_;
  const FaultSink& faults_;
  MotionOutputTelemetry tel_;
};

}  // namespace carril::fw
