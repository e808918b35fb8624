#include "host_sim/sensors/TapeWear.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace carril::sim {

namespace {
double length_of(const std::vector<Vec2>& pts) {
  double len = 0.0;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    len += std::hypot(pts[i + 1].x - pts[i].x, pts[i + 1].y - pts[i].y);
  }
  return len;
}
}  // namespace

std::vector<std::vector<TapeGap>> tape_gaps(const Scenario& s, std::uint64_t seed) {
  std::vector<std::vector<TapeGap>> all(s.lines.size());
  const TapeWearSpec& w = s.tape_wear;
  if (w.gaps_per_m <= 0.0) return all;
  // Its own generator: the wear does not move any other draw of the run.
  std::mt19937_64 rng(seed ^ 0x7A9E3EA2ULL);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t k = 0; k < s.lines.size(); ++k) {
    const double len = length_of(s.lines[k].points);
    const int n = int(std::floor(w.gaps_per_m * len + u(rng)));
    for (int i = 0; i < n; ++i) {
      const double at = u(rng) * len;
      all[k].push_back({at, at + w.gap_length_m});
    }
    std::sort(all[k].begin(), all[k].end(),
              [](const TapeGap& a, const TapeGap& b) { return a.from_m < b.from_m; });
  }
  return all;
}

std::vector<std::vector<Vec2>> tape_pieces(const std::vector<Vec2>& pts,
                                           const std::vector<TapeGap>& gaps) {
  std::vector<std::vector<Vec2>> pieces;
  if (gaps.empty()) {
    pieces.push_back(pts);
    return pieces;
  }
  // Walk the line; `in_gap` holds while the arc length is inside any gap.
  const auto inside = [&](double s) {
    for (const TapeGap& g : gaps) {
      if (s >= g.from_m && s <= g.to_m) return true;
    }
    return false;
  };
  std::vector<Vec2> cur;
  double s = 0.0;
  const auto close = [&] {
    if (cur.size() >= 2) pieces.push_back(cur);
    cur.clear();
  };
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    const Vec2 a = pts[i], b = pts[i + 1];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    if (len < 1e-12) continue;
    // Events on this segment: its ends and every gap edge inside it.
    std::vector<double> cuts = {s, s + len};
    for (const TapeGap& g : gaps) {
      for (const double e : {g.from_m, g.to_m}) {
        if (e > s && e < s + len) cuts.push_back(e);
      }
    }
    std::sort(cuts.begin(), cuts.end());
    for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
      const double s0 = cuts[c], s1 = cuts[c + 1];
      const auto at = [&](double q) {
        const double f = (q - s) / len;
        return Vec2{a.x + (b.x - a.x) * f, a.y + (b.y - a.y) * f};
      };
      if (inside(0.5 * (s0 + s1))) {
        close();
        continue;
      }
      if (cur.empty()) cur.push_back(at(s0));
      cur.push_back(at(s1));
    }
    s += len;
  }
  close();
  return pieces;
}

Rgb faded(Rgb tape, Rgb floor, double fade) {
  const auto mix = [&](std::uint8_t t, std::uint8_t f) {
    return static_cast<std::uint8_t>(std::lround(double(t) + (double(f) - double(t)) * fade));
  };
  return Rgb{mix(tape.r, floor.r), mix(tape.g, floor.g), mix(tape.b, floor.b)};
}

}  // namespace carril::sim
