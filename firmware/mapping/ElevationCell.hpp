#pragma once
// One cell of the elevation map: a height estimate and its variance (elevation_mapping's model),
// kept in the odometry frame. The unit of saved elevation maps too.

namespace carril::fw {

struct ElevationCell {
  float height_m = 0.0F;     // ground height, odometry frame [m]
  float variance_m2 = 0.0F;  // of height_m [m^2]; 0 = never observed
  bool observed() const { return variance_m2 > 0.0F; }
};

}  // namespace carril::fw
