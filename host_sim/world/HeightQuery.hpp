#pragma once
// The simulated world's surface as the 3D lidar sees it: ground height from the terrain plus the
// tops of obstacles (vertical prisms). Implemented by the world's height field; the simulated 3D
// lidar casts its rays against it.

namespace carril::sim {

class HeightQuery {
 public:
  virtual ~HeightQuery() = default;
  // Surface height at world point (x, y) [m]: terrain, or an obstacle's top where one stands.
  virtual double height_at(double x, double y) const = 0;
  // An upper bound of height_at over the whole world [m] (a ray above it hits nothing).
  virtual double max_height() const = 0;
  // A lower bound of height_at over the whole world [m] (trenches, pits).
  virtual double min_height() const = 0;
};

}  // namespace carril::sim
