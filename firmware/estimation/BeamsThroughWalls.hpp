#pragma once
// Negative information for a pose hypothesis: how many of a scan's returns, seen from a map pose,
// would have passed through cells the map marks occupied on their way out. The likelihood field
// (LikelihoodField.hpp) scores only where a beam ends, so a wrong pose among alike aisles or rooms
// can score well with beams that cross the map's walls; at the right pose almost none do. Things
// the map does not show (a box, a person) only shorten beams and do not count: the check is
// robust to clutter, which an absolute bound on the likelihood is not.
#include "firmware/core/Geometry.hpp"
#include "firmware/mapping/OccupancyGrid.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

struct BeamsThroughWalls {
  int checked = 0;  // valid returns walked
  int through = 0;  // of those, the ones that crossed an occupied cell
  // through / checked; 0 with nothing checked.
  double fraction() const { return checked > 0 ? double(through) / double(checked) : 0.0; }
};

// Walks the returns an update weighs (for_each_weighed_beam, ScanBeams.hpp: up to max_beams
// valid ones, evenly spaced) through the map's cells from
// margin_m past the sensor to margin_m short of the return, exactly (every cell the segment
// touches); a beam counts as through if one of those cells is occupied (cost::kLethal). The
// margins absorb the pose's error and the map's resolution where a beam grazes a wall; unknown
// cells and cells outside the map do not count. pose: the robot's map pose; laser_mount: the
// scanner in the robot frame [m, m, rad]. No allocation: cheap enough for every scan.
BeamsThroughWalls beams_through_walls(const OccupancyGrid& map, const hal::LaserScan& scan,
                                      const Pose2& pose, const Pose2& laser_mount, int max_beams,
                                      double max_range_m, double margin_m);

}  // namespace carril::fw
