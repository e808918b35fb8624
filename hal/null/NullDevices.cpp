#include "hal/null/NullDevices.hpp"

namespace carril::hal {

void NullWheelDrives::read(WheelFeedbackSet& out) const {
  out = {};
  out.count = static_cast<std::uint8_t>(count_);
}

}  // namespace carril::hal
