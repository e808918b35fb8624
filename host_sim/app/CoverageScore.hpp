#pragma once
// Scores a coverage run from the true pose: the cells the tool really swept (the same
// fw::CoverageGrid the mission keeps from its own pose), over the area a robot of this size can
// sweep from its start (fw::CoverageArea: the map's free space reachable by its centre, widened
// by the tool's reach), and writes the heat map coverage.png.
#include <memory>
#include <optional>
#include <string>

#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/mapping/CoverageGrid.hpp"
#include "firmware/planning/CoverageArea.hpp"
#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim {

struct CoverageFigures {
  double covered = 0.0;        // swept fraction of the coverable area [0, 1]
  double overlap = 0.0;        // of the swept cells, the fraction swept more than once [0, 1]
  double area_m2 = 0.0;        // the coverable area [m^2]
  double lower_bound_s = 0.0;  // area / (tool width x mission speed) [s]
};

class CoverageScore {
 public:
  // Throws std::invalid_argument (naming the scenario) when the area cannot be built.
  CoverageScore(const Scenario& s, const fw::FirmwareConfig& c, const fw::OccupancyGrid& map);
  // The robot's true pose after a tick.
  void add(const Pose2& true_pose);
  CoverageFigures figures() const;
  // coverage.png in dir: per cell how often it was swept; false with error on a failed write.
  bool write_png(const std::string& dir, std::string& error) const;

 private:
  double tool_m_, speed_mps_;
  fw::CoverageArea area_;
  fw::CoverageGrid grid_;
  const fw::OccupancyGrid& map_;
  std::optional<fw::Pose2> last_;
};

}  // namespace carril::sim
