#include "host_sim/sensors/WheelEncoderSim.hpp"

namespace carril::sim {

WheelEncoderSim::WheelEncoderSim(const OdometryErrorSpec& spec, std::uint64_t seed)
    : spec_(spec), rng_(seed ^ 0x0D0E7A1DULL) {}

void WheelEncoderSim::read(int i, hal::TimeNs t_ns, float true_radps, double true_pos_rad,
                           float& radps, double& pos_rad) {
  if (!spec_.any()) {
    radps = true_radps;
    pos_rad = true_pos_rad;
    return;
  }
  Wheel& w = wheels_[std::size_t(i)];
  if (spec_.slip > 0.0 && t_ns >= w.next_draw_ns) {
    w.slip = spec_.slip * gauss_(rng_);
    w.next_draw_ns = t_ns + kSlipPeriodNs;
  }
  const double k = (1.0 + spec_.wheel_radius_error) * (1.0 + w.slip);
  if (!w.primed) {
    w.primed = true;
    w.pos = true_pos_rad;
  } else {
    w.pos += (true_pos_rad - w.last_true_pos) * k;
  }
  w.last_true_pos = true_pos_rad;
  radps = float(true_radps * k);
  pos_rad = w.pos;
}

}  // namespace carril::sim
