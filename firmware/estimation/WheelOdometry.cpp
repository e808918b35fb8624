#include "firmware/estimation/WheelOdometry.hpp"

namespace carril::fw {

void WheelOdometry::run() {
  const SensorFrame& f = frame_.get();
  odom_.update(f.wheels);
  OdometryMsg& m = out_.edit();
  m.pose = odom_.pose();
  m.twist = odom_.twist();
  out_.publish(f.now_ns);
}

}  // namespace carril::fw
