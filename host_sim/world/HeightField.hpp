#pragma once
// The simulated world's surface, built once from the scenario's terrain and obstacles:
// analytic (each feature a closed-form height over its rectangle), exact at any point, no grid.
// Where features overlap the highest wins; outside every feature the floor is at z = 0.
// Metres; world frame (x, y), z up.
#include <vector>

#include "host_sim/scenario/Scenario.hpp"
#include "host_sim/world/HeightQuery.hpp"

namespace carril::sim {

// The ground at one point: height [m] and its gradient (dz/dx, dz/dy) [m/m]; the gradient is
// that of the feature that gives the height (0 on flat parts and on the floor).
struct GroundSample {
  double z_m = 0.0;
  double dzdx = 0.0, dzdy = 0.0;
};

class HeightField final : public HeightQuery {
 public:
  HeightField(const std::vector<TerrainSpec>& terrain, const std::vector<ObstacleSpec>& obstacles);
  explicit HeightField(const Scenario& s) : HeightField(s.terrain, s.obstacles) {}

  // Surface height at (x, y) [m]: the ground, or an obstacle's top where one stands.
  double height_at(double x, double y) const override;
  double max_height() const override { return max_z_; }  // [m]
  double min_height() const override { return min_z_; }  // [m]

  // The ground alone (terrain, no obstacles: those are Box2D's walls for the wheels) [m].
  double ground_at(double x, double y) const { return ground_sample(x, y).z_m; }
  GroundSample ground_sample(double x, double y) const;

 private:
  // One feature in its own frame: u along its x (yaw), v across; |u| <= hu, |v| <= hv.
  struct Feature {
    double cx = 0.0, cy = 0.0, c = 1.0, s = 0.0, hu = 0.0, hv = 0.0;
    double xmin = 0.0, xmax = 0.0, ymin = 0.0, ymax = 0.0;  // world bounding box
    TerrainType type = TerrainType::Step;
    double z = 0.0;  // step / trench: the constant height [m]
    // Ramp profile from its low end (u = -hu): knots at these distances, linear in between.
    double knot_s[6] = {}, knot_z[6] = {};
    int knots = 0;
  };
  struct Top {  // an obstacle: vertical prism up to z_top
    bool box = true;
    double cx = 0.0, cy = 0.0, c = 1.0, s = 0.0, hx = 0.0, hy = 0.0, r = 0.0, z_top = 0.0;
  };

  static bool profile(const Feature& f, double u, double& z, double& dzdu);

  std::vector<Feature> features_;
  std::vector<Top> tops_;
  double max_z_ = 0.0, min_z_ = 0.0;
};

}  // namespace carril::sim
