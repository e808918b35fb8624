#pragma once
#include "hal/Types.hpp"

namespace carril::hal {

class RangeScanner {
 public:
  virtual ~RangeScanner() = default;
  // Newest complete scan, or nullptr if none has arrived. Valid until the next call.
  virtual const LaserScan* latest() = 0;
};

}  // namespace carril::hal
