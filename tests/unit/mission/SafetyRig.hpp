#pragma once
// What the safety tests share: the fields' configuration (reaction 0.08 s, braking 1 m/s^2) and
// a field from one 360 deg scan of a scene by a lidar at the centre of a robot at the origin.
#include <cmath>

#include "firmware/mission/SafetyFields.hpp"
#include "firmware/msg/ObstacleField.hpp"
#include "tests/unit/perception/ScanScene.hpp"

namespace carril::fw::test {

inline SafetyFieldsConfig safety_fields_config() {
  SafetyFieldsConfig c;
  c.scan_period_s = 0.05;
  c.tick_s = 0.01;
  c.drive_latency_s = 0.02;  // reaction 0.08 s
  c.decel_mps2 = 1.0;
  return c;
}

inline ObstacleField field_of(const Footprint& fp, const ScanScene& scene, double fov_deg = 360.0) {
  ObstacleField f(fp, 0.0, 0.0, 0.0);
  auto s = scene.scan(Pose2{}, Pose2{}, 1441, fov_deg * kPi / 180.0);
  f.update(*s, Pose2{});
  return f;
}

}  // namespace carril::fw::test
