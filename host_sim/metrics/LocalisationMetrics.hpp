#pragma once
// Scores the firmware's localisation against the true pose, tick by tick: when the estimate
// converged (the first time it came within 0.2 m and 5 deg and stayed there), the error after
// convergence (RMSE and maximum, in position and yaw), and after each kidnap (the robot moved by
// the scenario) how long until it was back within those bounds for good.
#include <optional>
#include <vector>

namespace carril::sim {

struct LocalisationScore {
  std::optional<double> time_to_converge_s;  // from the start; null: never converged
  double rmse_m = 0.0;                       // position error RMS after convergence [m]
  double max_error_m = 0.0;                  // largest position error after convergence [m]
  double yaw_rmse_deg = 0.0;                 // yaw error RMS after convergence [deg]
  long converged_ticks = 0;                  // ticks the three figures above are taken over
  // Per kidnap: the time from the kidnap until the estimate was within bounds for good (null:
  // not before the run ended or the next kidnap).
  std::vector<std::optional<double>> relocalised_after_s;
};

class LocalisationMetrics {
 public:
  static constexpr double kConvergedM = 0.2;    // [m]
  static constexpr double kConvergedDeg = 5.0;  // [deg]

  // One tick: position error [m] and absolute yaw error [rad] of the estimate.
  void add(double t_s, double error_m, double yaw_error_rad);
  // The robot was teleported at t_s (the estimate is then expected to be wrong).
  void kidnap(double t_s);
  LocalisationScore score() const;
  bool empty() const { return ticks_.empty(); }

 private:
  struct Tick {
    double t_s, error_m, yaw_error_rad;
  };
  // The first index in [begin, end) from which every tick is within bounds; end if none.
  std::size_t settled_from(std::size_t begin, std::size_t end) const;
  std::vector<Tick> ticks_;
  std::vector<std::size_t> kidnaps_;  // index of the first tick after each kidnap
  std::vector<double> kidnap_t_s_;
};

}  // namespace carril::sim
