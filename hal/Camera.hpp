#pragma once
#include "hal/Types.hpp"

namespace carril::hal {

class Camera {
 public:
  virtual ~Camera() = default;
  // Newest complete frame, or nullptr if none has arrived. Valid until the next call.
  virtual const CameraFrame* latest() = 0;
};

}  // namespace carril::hal
