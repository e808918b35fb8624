#pragma once
#include "hal/Types.hpp"

namespace carril::hal {

class Imu {
 public:
  virtual ~Imu() = default;
  // Newest sample; valid=false when the sensor has not answered.
  virtual ImuSample read() = 0;
};

}  // namespace carril::hal
