#pragma once
// --view: a live OpenCV window with the top view (tape, obstacles, robot, path) beside the
// robot's camera image. Host tool only; never part of a firmware build.
#include <memory>
#include <string>

#include "host_sim/app/SimRun.hpp"

namespace carril::sim {

class LiveView {
 public:
  // Opens the window; nullptr with `why` set when there is no display.
  static std::unique_ptr<LiveView> open(const Scenario& scenario, std::string& why);
  ~LiveView();
  // Redraws about 30 times per simulated second; false when the user closed the window or
  // pressed q / Esc.
  bool update(SimRun& run, double dt_s);

 private:
  struct Impl;
  explicit LiveView(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace carril::sim
