// Fuzz target: scenario files (host_sim/scenario/ScenarioLoader), from text. The file is taken to
// sit in scenarios/, so `map: maps/house.yaml` reads the shipped map, and robot presets come from
// config/robots. Any input must load or give one message; a crash, leak or UB report is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "FuzzTempFiles.hpp"
#include "host_sim/scenario/ScenarioLoader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = CARRIL_SOURCE_DIR "/scenarios/fuzz-input.yaml";
  static const std::string robots = CARRIL_SOURCE_DIR "/config/robots";
  const std::string text(carril::fuzz::as_text(data, size));
  const carril::sim::LoadResult r = carril::sim::load_scenario_text(text, path, robots);
  carril::fuzz::print_outcome(r.ok, r.error);
  // The contract: a rejected file says why.
  if (!r.ok && r.error.empty()) std::abort();
  return 0;
}
