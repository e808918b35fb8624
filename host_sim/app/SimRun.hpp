#pragma once
// One simulated run in lockstep: each tick the simulator publishes the sensors that are due,
// runs one firmware step (inside an allocation-counting window), applies the drive setpoints,
// advances the physics by one period and scores the result.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "host_sim/app/CoverageScore.hpp"
#include "host_sim/app/SimTopology.hpp"
#include "host_sim/metrics/LocalisationMetrics.hpp"
#include "host_sim/metrics/RunMetrics.hpp"
#include "host_sim/output/RunOutputs.hpp"
#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim {

class SimRun {
 public:
  // The run keeps a reference to `scenario`, which must outlive it (a temporary may not).
  SimRun(const Scenario& scenario, std::uint64_t seed, const ConfigTweak& tweak = {});
  SimRun(Scenario&&, std::uint64_t, const ConfigTweak& = {}) = delete;

  // One tick. Returns false once the run has finished (end reached, time limit, fault).
  bool step();
  // Stop now (Ctrl-C); the run finishes as "aborted".
  void abort();
  bool finished() const { return !result_.empty(); }

  // The summary of the run so far, with the wall time it took.
  RunSummary summary(double wall_time_s);

  double sim_time_s() const { return double(tick_) * period_s_; }
  double progress() const { return metrics_.progress(); }
  const char* state_name() const;
  const std::vector<TrajectoryRow>& rows() const { return rows_; }
  const std::vector<CollisionPoint>& collisions() const { return collisions_; }
  // Firmware events (state changes, phases, faults) as log lines, since the last call.
  std::vector<std::string> take_log();
  // Task overrun events (throttled), as log lines, since the start of the run.
  const std::vector<std::string>& overrun_log() const { return overrun_log_; }
  SimTopology& topology() { return topo_; }
  const fw::Firmware& firmware() const { return *topo_.firmware; }
  const Scenario& scenario() const { return scenario_; }
  std::uint64_t allocations_in_ticks() const;
  // The coverage run's score from the true pose (nullptr for other missions).
  const CoverageScore* coverage() const { return coverage_.get(); }

 private:
  void publish_sensors(hal::TimeNs t);
  void drain_events();

  const Scenario& scenario_;
  SimTopology topo_;
  RunMetrics metrics_;
  LocalisationMetrics localisation_;
  std::unique_ptr<CoverageScore> coverage_;
  std::size_t next_kidnap_ = 0;
  double period_s_;
  hal::TimeNs period_ns_, cam_period_ns_, scan_period_ns_;
  hal::TimeNs next_cam_ns_ = 0, next_scan_ns_ = 0, next_cloud_ns_ = 0;
  std::uint64_t tick_ = 0;
  std::uint64_t alloc_base_ = 0;
  double fault_at_s_ = -1.0;
  std::string result_;  // empty while running
  std::vector<TrajectoryRow> rows_;
  std::vector<CollisionPoint> collisions_;
  std::vector<std::string> log_;
  std::vector<std::string> overrun_log_;
};

}  // namespace carril::sim
