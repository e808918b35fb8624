#pragma once
// Wheel speeds <-> body twist for the two drive types carril supports.
// Mecanum wheel order: front-left, front-right, rear-left, rear-right (rollers at 45 deg, "X"
// pattern seen from above). Differential: left, right (a skid-steer robot is treated as one).
#include <Eigen/Core>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

enum class DriveType : unsigned char { Differential, Mecanum };

// The wheel geometry's ranges, declared once: the robot file's loader and validate() both take
// them from here [m].
inline constexpr double kWheelRadiusMinM = 0.01, kWheelRadiusMaxM = 1.0;
inline constexpr double kWheelSpanMinM = 0.05, kWheelSpanMaxM = 5.0;  // wheelbase and track

struct DriveGeometry {
  DriveType type = DriveType::Differential;
  double wheel_radius_m = 0.1;  // [m]
  double wheelbase_m = 0.4;     // front-rear axle distance (mecanum) [m]
  double track_m = 0.4;         // left-right wheel distance [m]

  Status validate() const;
  bool operator==(const DriveGeometry&) const = default;
};

class DriveKinematics {
 public:
  explicit DriveKinematics(const DriveGeometry& g);

  int wheel_count() const { return n_; }
  DriveType type() const { return g_.type; }
  bool holonomic() const { return g_.type == DriveType::Mecanum; }

  // Wheel speeds [rad/s] for a body twist; a differential drive ignores vy.
  void inverse(const Twist& t, float* wheel_radps) const;
  // Body twist from wheel speeds [rad/s] (least squares for mecanum's 4 wheels).
  Twist forward(const float* wheel_radps) const;
  // Same, from wheel angle increments [rad]: a body displacement (dx, dy, dyaw) over the step.
  Twist forward_delta(const double* wheel_delta_rad) const;

 private:
  DriveGeometry g_;
  int n_;
  Eigen::Matrix<double, 4, 3> inv_;  // rows: wheels (first n_ used)
  Eigen::Matrix<double, 3, 4> fwd_;  // columns: wheels (first n_ used)
};

}  // namespace carril::fw
