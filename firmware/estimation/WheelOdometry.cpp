#include "firmware/estimation/WheelOdometry.hpp"

#include <cmath>

namespace carril::fw {

void WheelOdometry::run() {
  const SensorFrame& f = frame_.get();
  odom_.update(f.wheels, f.imu);
  OdometryMsg& m = out_.edit();
  if (tel_.updates > 0) {
    tel_.distance_m += std::hypot(odom_.pose().x - m.pose.x, odom_.pose().y - m.pose.y);
  }
  ++tel_.updates;
  tel_.gyro_steps = odom_.gyro_steps();
  tel_.wheel_steps = odom_.wheel_steps();
  m.pose = odom_.pose();
  m.twist = odom_.twist();
  out_.publish(f.now_ns);
}

}  // namespace carril::fw
