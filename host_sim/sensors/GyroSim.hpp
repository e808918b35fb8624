#pragma once
// The IMU's yaw-rate gyro as the firmware reads it: the body's true yaw rate plus the robot
// file's constant bias and white noise (imu.gyro_bias_radps, imu.gyro_noise_std_radps).
// Deterministic for a seed; with neither set the truth passes through untouched.
#include <cstdint>
#include <random>

#include "host_sim/sensors/Normal.hpp"
#include "loader/RobotSpec.hpp"

namespace carril::sim {

class GyroSim {
 public:
  GyroSim(const loader::ImuSpec& spec, std::uint64_t seed)
      : noise_(spec.gyro_noise_std_radps), bias_(spec.gyro_bias_radps), rng_(seed ^ 0x6B1A5ULL) {}

  // One sample: the true yaw rate [rad/s] in, the gyro's reading out [rad/s].
  float read(double true_radps) {
    if (noise_ <= 0.0) return float(true_radps + bias_);
    return float(true_radps + bias_ + noise_ * gauss_(rng_));
  }

 private:
  double noise_, bias_;
  std::mt19937_64 rng_;
  Normal gauss_{0.0, 1.0};
};

}  // namespace carril::sim
