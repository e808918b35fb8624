#pragma once
// carril_sim --hil: options and the real-time loop around HilRun (HilRun.hpp).
#include <atomic>
#include <string>
#include <vector>

#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim {

struct HilOptions {
  std::string can_iface;                // --can IFACE (SocketCAN)
  std::string controller_path;          // --controller FILE: the drives' node ids and units
  std::string can_log;                  // --can-log FILE ("" none)
  int scip_port = 10940;                // --scip-port N (0: no lidar server)
  std::string shm = "/carril_sensors";  // --shm NAME ("" none)
  double duration_s = 0.0;              // --duration S (0: the scenario's)
  std::vector<std::string> inject;      // --inject T:DRIVE:WHAT
};

// Runs the HIL world in real time until the duration or a signal (`signal` != 0); writes
// out_dir/hil_summary.json (and the CAN log). Returns carril_sim's exit status: 0 ran, 2 bad
// input (an error naming the option, file or interface is printed).
int run_hil(const Scenario& scenario, std::uint64_t seed, const std::string& out_dir,
            const HilOptions& opt, const std::atomic<int>& signal);

}  // namespace carril::sim
