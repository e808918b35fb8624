#pragma once
// Message `costmap`: what the missions read of the costmap, the master grid (every layer combined
// and inflated) and a counter that changes whenever the master is rebuilt. A read-only view:
// implemented by the mapping component (firmware/mapping/Mapping), which publishes it on the bus
// once at init; a test can implement it over any grid.
#include <cstdint>

#include "firmware/core/Check.hpp"
#include "firmware/core/RollingGrid.hpp"
#include "firmware/core/Topic.hpp"

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

// The view of no costmap: grids never set up (ready() false), never built (updates() 0): a mission
// handed it waits for a costmap as at start-up, and its wait times out to a safe stop.
class EmptyCostmapView final : public CostmapView {
 public:
  const RollingGrid<std::uint8_t>& master() const override { return none_; }
  const RollingGrid<std::uint8_t>& obstacles() const override { return none_; }
  std::uint32_t updates() const override { return 0; }

 private:
  RollingGrid<std::uint8_t> none_;
};

// A component's read of the costmap topic, the one way every consumer reaches the view.
class CostmapInput {
 public:
  CostmapInput() = default;
  explicit CostmapInput(const Topic<CostmapMsg>& topic) : topic_(&topic) {}
  void watch(const Topic<CostmapMsg>& topic) { topic_ = &topic; }
  // nullptr when no costmap is built, or before the topic is watched.
  const CostmapView* view() const { return topic_ != nullptr ? topic_->get().view : nullptr; }
  // For a component whose configuration requires a costmap (validate() refuses it without one):
  // the view; none is a programming error, checked, with the empty view as the safe way out.
  const CostmapView& get() const {
    const CostmapView* v = view();
    if (v != nullptr) return *v;
    (void)CARRIL_CHECK(v != nullptr);
    return empty_;
  }

 private:
  const Topic<CostmapMsg>* topic_ = nullptr;
  EmptyCostmapView empty_;
};

}  // namespace carril::fw
