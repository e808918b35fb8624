#pragma once
// Message `costmap`: what the missions read of the costmap, the master grid (every layer combined
// and inflated) and a counter that changes whenever the master is rebuilt. A read-only view:
// implemented by the mapping component (firmware/mapping/Mapping), which publishes it on the bus
// once at init; a test can implement it over any grid.
#include <cstdint>

#include "firmware/core/RollingGrid.hpp"

namespace carril::fw {

class CostmapView {
 public:
  virtual ~CostmapView() = default;
  // The combined, inflated costs (Nav2 values, firmware/mapping/CostValues.hpp).
  virtual const RollingGrid<std::uint8_t>& master() const = 0;
  // The 2D lidar's obstacle layer alone (lethal = a return was seen there).
  virtual const RollingGrid<std::uint8_t>& obstacles() const = 0;
  // The static map's layer (lethal where the map is occupied), the same window as obstacles();
  // nullptr off a map. With obstacles(), what a body can touch (master() adds terrain a wheel
  // must not cross, and inflation).
  virtual const RollingGrid<std::uint8_t>* walls() const { return nullptr; }
  // Increments at every rebuild of master(); 0 = never built.
  virtual std::uint32_t updates() const = 0;
};

// The costmap topic's message: the view, published once by its owner (nullptr: no costmap is
// built, as when FirmwareConfig::mapping is off).
struct CostmapMsg {
  const CostmapView* view = nullptr;
};

}  // namespace carril::fw
