#include "firmware/control/MotionOutput.hpp"

namespace carril::fw {

MotionOutput::MotionOutput(const MotionLimits& limits, const DriveKinematics& kin, double period_s,
                           const Topic<SensorFrame>& frame, const Topic<MotionRequest>& request,
                           Topic<ActuatorCommand>& out, const FaultSink& faults)
    : kin_(kin),
      limiter_(limits, kin, period_s),
      frame_(frame),
      request_(request),
      out_(out),
      faults_(faults) {
  out_.edit().wheel_count = static_cast<std::uint8_t>(kin.wheel_count());
}

void MotionOutput::run() {
  const SensorFrame& f = frame_.get();
  ActuatorCommand& cmd = out_.edit();
  if (faults_.latched()) {
    quick_stop(cmd);
    limiter_.reset();
    ++tel_.quick_stops;
  } else {
    Twist want = request_.get().twist;
    if (!drives_enabled(f.wheels, kin_.wheel_count())) {
      want = {};
      limiter_.reset();
      ++tel_.drives_not_ready;
    }
    cmd.drive = DriveRequest::Run;
    cmd.twist = limiter_.apply(want, cmd.wheel_radps.data());
  }
  ++tel_.commands;
  out_.publish(f.now_ns);
}

}  // namespace carril::fw
