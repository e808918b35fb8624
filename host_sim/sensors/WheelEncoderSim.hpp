#pragma once
// The wheel encoders as the firmware reads them, with odometry drift (a scenario's `odometry:`
// section): a wrong wheel radius scales every wheel's reading, wheel slip perturbs each wheel's
// reading by a Gaussian fraction redrawn every 0.1 s. Positions are integrated from the
// perturbed increments, so position and speed stay consistent, as a real encoder's are.
#include <array>
#include <cstdint>
#include <random>

#include "hal/Types.hpp"
#include "host_sim/scenario/Scenario.hpp"
#include "host_sim/sensors/Normal.hpp"

namespace carril::sim {

class WheelEncoderSim {
 public:
  WheelEncoderSim(const OdometryErrorSpec& spec, std::uint64_t seed);

  // One reading of wheel i at time t: the true speed [rad/s] and position [rad] in, what the
  // encoder reports out.
  void read(int i, hal::TimeNs t_ns, float true_radps, double true_pos_rad, float& radps,
            double& pos_rad);

 private:
  static constexpr hal::TimeNs kSlipPeriodNs = 100'000'000;
  OdometryErrorSpec spec_;
  std::mt19937_64 rng_;
  Normal gauss_{0.0, 1.0};
  struct Wheel {
    bool primed = false;
    double last_true_pos = 0.0, pos = 0.0;
    double slip = 0.0;  // the current slip fraction
    hal::TimeNs next_draw_ns = 0;
  };
  std::array<Wheel, hal::kMaxWheels> wheels_{};
};

}  // namespace carril::sim
