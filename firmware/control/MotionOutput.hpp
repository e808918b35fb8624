#pragma once
// Component: the last stage before the drives. Takes the mission runner's motion request, makes
// it feasible (MotionLimiter: speed, acceleration and wheel-speed limits) and publishes the
// actuator command; zero while the drives are not all enabled, and a quick stop once a fault has
// latched, whatever was requested.
#include "firmware/control/MotionLimiter.hpp"
#include "firmware/control/MotionRequest.hpp"
#include "firmware/core/FaultSink.hpp"
#include "firmware/core/Frames.hpp"
#include "firmware/core/Topic.hpp"

namespace carril::fw {

class MotionOutput {
 public:
  MotionOutput(const MotionLimits& limits, const DriveKinematics& kin, double period_s,
               const Topic<SensorFrame>& frame, const Topic<MotionRequest>& request,
               Topic<ActuatorCommand>& out, const FaultSink& faults);

  // Task: one actuator command.
  void run();

 private:
  const DriveKinematics& kin_;
  MotionLimiter limiter_;
  const Topic<SensorFrame>& frame_;
  const Topic<MotionRequest>& request_;
  Topic<ActuatorCommand>& out_;
  const FaultSink& faults_;
};

}  // namespace carril::fw
