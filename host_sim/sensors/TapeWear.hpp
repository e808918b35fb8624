#pragma once
// Worn tape for the camera renderer: the stretches of a tape's centre line that are left once the
// gaps of a TapeWearSpec are cut out, and the faded colour.
#include <cstdint>
#include <vector>

#include "host_sim/scenario/Scenario.hpp"

namespace carril::sim {

// A gap along a tape, by arc length from its first point [m].
struct TapeGap {
  double from_m = 0.0, to_m = 0.0;
};

// The gaps of every line of `s` (one list per line, sorted, possibly overlapping): per line,
// floor(gaps_per_m x length + u) gaps (u uniform in [0, 1), so the mean is gaps_per_m x length),
// each gap_length_m long at a uniform place; drawn from `seed`, the same for the same scenario.
std::vector<std::vector<TapeGap>> tape_gaps(const Scenario& s, std::uint64_t seed);

// The stretches of polyline `pts` outside `gaps` (sorted by from_m), each a polyline of at least
// two points; the whole line when there is no gap.
std::vector<std::vector<Vec2>> tape_pieces(const std::vector<Vec2>& pts,
                                           const std::vector<TapeGap>& gaps);

// The tape's colour faded toward the floor's by `fade` (0: unchanged, 1: the floor's).
Rgb faded(Rgb tape, Rgb floor, double fade);

}  // namespace carril::sim
