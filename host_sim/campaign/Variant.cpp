#include "host_sim/campaign/Variant.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "host_sim/scenario/ScenarioLoader.hpp"
#include "loader/StrictYaml.hpp"
#include "loader/YamlPrecheck.hpp"

#include "firmware/core/Geometry.hpp"

namespace carril::sim::campaign {

namespace {
namespace fs = std::filesystem;
using fw::kPi;  // the one pi, firmware/core/Geometry.hpp

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 0xCBF29CE484222325ULL;
  for (const unsigned char c : s) h = (h ^ c) * 0x100000001B3ULL;
  return h;
}

// Values go into the scenario file as text: rounded to 1e-6 so the file, the CSV and a replay
// agree on every digit.
double rounded(double v) {
  return std::round(v * 1e6) / 1e6;
}

std::string text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6f", rounded(v));
  std::string s(buf);
  while (!s.empty() && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.push_back('0');
  if (s == "-0.0") s = "0.0";
  return s;
}

double draw(const CampaignSpec& spec, std::uint64_t index, const Perturbation& p) {
  const Distribution& d = p.dist;
  switch (d.kind) {
    case Distribution::Kind::Fixed:
      return d.a;
    case Distribution::Kind::Uniform:
      return rounded(d.a + (d.b - d.a) * unit_draw(draw_key(spec.seed, index, p.key, 0)));
    case Distribution::Kind::Normal:
      // Box-Muller, drawn again outside the clip (the mean is inside it, so this ends).
      for (std::uint64_t k = 0; k < 2000; k += 2) {
        const double u1 = unit_draw(draw_key(spec.seed, index, p.key, k));
        const double u2 = unit_draw(draw_key(spec.seed, index, p.key, k + 1));
        const double z = std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(2.0 * kPi * u2);
        const double v = rounded(d.a + d.b * z);
        if (v >= d.clip_lo && v <= d.clip_hi) return v;
      }
      return d.a;
  }
  return d.a;
}

double number_at(const YAML::Node& n, double fallback) {
  return n && n.IsScalar() ? n.as<double>() : fallback;
}

double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
  const double t =
      l2 > 0.0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / l2, 0.0, 1.0) : 0.0;
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

double polyline_distance(const Vec2& p, const std::vector<Vec2>& pts) {
  double d = pts.size() == 1 ? std::hypot(p.x - pts[0].x, p.y - pts[0].y) : 1e18;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    d = std::min(d, segment_distance(p, pts[i], pts[i + 1]));
  }
  return d;
}

// `count` cylinders of radius 0.1-0.25 m at places drawn in the walls' bounding box (else the
// tape's, 1.5 m wider), each kept kTapeClear from the tape, kStartClear from the start, 0.1 m from
// walls and 0.3 m from other obstacles; one that finds no such place in 200 draws is left out.
void add_obstacles(int count, const Variant& v, const CampaignSpec& spec, YAML::Node& root) {
  constexpr double kTapeClear = 0.5, kStartClear = 1.0;
  const LoadResult base = load_scenario(spec.scenarios.at(v.scenario), default_robots_dir());
  if (!base.ok) throw std::runtime_error(base.error);
  const Scenario& s = base.scenario;
  double x0 = 1e18, x1 = -1e18, y0 = 1e18, y1 = -1e18;
  const auto grow = [&](const Vec2& p) {
    x0 = std::min(x0, p.x);
    x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y);
    y1 = std::max(y1, p.y);
  };
  for (const WallSpec& w : s.walls) {
    for (const Vec2& p : w.points) grow(p);
  }
  if (s.walls.empty()) {
    for (const LineSpec& l : s.lines) {
      for (const Vec2& p : l.points) grow(p);
    }
    x0 -= 1.5;
    x1 += 1.5;
    y0 -= 1.5;
    y1 += 1.5;
  }
  if (!(x1 > x0 && y1 > y0)) return;
  struct Disc {
    Vec2 c;
    double r;
  };
  std::vector<Disc> taken;
  for (const ObstacleSpec& o : s.obstacles) {
    taken.push_back({o.center, o.shape == ObstacleShape::Box
                                   ? 0.5 * std::hypot(o.size_x_m, o.size_y_m)
                                   : o.radius_m});
  }
  if (!root["obstacles"] || !root["obstacles"].IsSequence()) {
    root["obstacles"] = YAML::Node(YAML::NodeType::Sequence);
  }
  std::uint64_t k = 1000;  // draws of this key after the jitter's
  for (int n = 0; n < count; ++n) {
    for (int attempt = 0; attempt < 200; ++attempt) {
      const double r = 0.1 + 0.15 * unit_draw(draw_key(spec.seed, v.index, "extra_obstacles", k++));
      const Vec2 c{
          x0 + 0.4 +
              (x1 - x0 - 0.8) * unit_draw(draw_key(spec.seed, v.index, "extra_obstacles", k++)),
          y0 + 0.4 +
              (y1 - y0 - 0.8) * unit_draw(draw_key(spec.seed, v.index, "extra_obstacles", k++))};
      bool ok = std::hypot(c.x - s.robot.start.x, c.y - s.robot.start.y) >= r + kStartClear;
      for (const LineSpec& l : s.lines) ok = ok && polyline_distance(c, l.points) >= r + kTapeClear;
      for (const WallSpec& w : s.walls) {
        ok = ok && polyline_distance(c, w.points) >= r + 0.5 * w.thickness_m + 0.1;
      }
      for (const Disc& d : taken) ok = ok && std::hypot(c.x - d.c.x, c.y - d.c.y) >= r + d.r + 0.3;
      if (!ok) continue;
      taken.push_back({c, r});
      YAML::Node o(YAML::NodeType::Map);
      o.SetStyle(YAML::EmitterStyle::Flow);
      o["shape"] = "cylinder";
      o["x"] = text(c.x);
      o["y"] = text(c.y);
      o["radius_m"] = text(r);
      root["obstacles"].push_back(o);
      break;
    }
  }
}

void apply(const std::string& key, double value, const Variant& v, const CampaignSpec& spec,
           YAML::Node& root) {
  if (key == "start_offset_m" || key == "start_heading_deg") {
    YAML::Node start = root["robot"]["start"];
    const double x = number_at(start["x"], 0.0), y = number_at(start["y"], 0.0);
    const double yaw_deg = number_at(start["yaw_deg"], 0.0);
    YAML::Node out(YAML::NodeType::Map);
    out.SetStyle(YAML::EmitterStyle::Flow);
    const double yaw = yaw_deg * kPi / 180.0;
    const bool offset = key == "start_offset_m";
    out["x"] = text(offset ? x - std::sin(yaw) * value : x);
    out["y"] = text(offset ? y + std::cos(yaw) * value : y);
    out["yaw_deg"] = text(offset ? yaw_deg : yaw_deg + value);
    root["robot"]["start"] = out;
  } else if (key == "camera_noise") {
    root["robot"]["camera"]["noise_std"] = text(value);
  } else if (key == "lidar_noise_m") {
    root["robot"]["lidar"]["noise_std_m"] = text(value);
  } else if (key == "wheel_slip") {
    root["odometry"]["slip"] = text(value);
  } else if (key == "wheel_radius_error") {
    root["odometry"]["wheel_radius_error"] = text(value);
  } else if (key == "tape_gaps_per_m") {
    root["tape_wear"]["gaps_per_m"] = text(value);
  } else if (key == "tape_gap_length_m") {
    root["tape_wear"]["gap_length_m"] = text(value);
  } else if (key == "tape_fade") {
    root["tape_wear"]["fade"] = text(value);
  } else if (key == "floor_brightness") {
    YAML::Node c = root["floor"]["color"];
    const bool given = c && c.IsSequence() && c.size() == 3;
    YAML::Node out(YAML::NodeType::Sequence);
    out.SetStyle(YAML::EmitterStyle::Flow);
    for (std::size_t k = 0; k < 3; ++k) {
      const double base = given ? c[k].as<double>() : 128.0;  // the format's default floor
      out.push_back(std::to_string(std::lround(std::min(255.0, base * value))));
    }
    root["floor"]["color"] = out;
  } else if (key == "floor_speckle") {
    root["floor"]["speckle"] = text(value);
  } else if (key == "camera_exposure") {
    root["robot"]["camera"]["exposure"] = text(value);
  } else if (key == "glare_intensity") {
    root["glare"]["intensity"] = text(value);
  } else if (key == "lidar_dropout") {
    root["robot"]["lidar"]["dropout"] = text(value);
  } else if (key == "extra_obstacles") {
    add_obstacles(int(std::floor(value + 0.5)), v, spec, root);
  } else if (key == "obstacle_jitter_m") {
    YAML::Node obstacles = root["obstacles"];
    if (!obstacles || !obstacles.IsSequence()) return;
    for (std::size_t j = 0; j < obstacles.size(); ++j) {
      YAML::Node o = obstacles[j];
      const double r = value * std::sqrt(unit_draw(draw_key(spec.seed, v.index, key, 2 * j + 1)));
      const double a = 2.0 * kPi * unit_draw(draw_key(spec.seed, v.index, key, 2 * j + 2));
      o["x"] = text(number_at(o["x"], 0.0) + r * std::cos(a));
      o["y"] = text(number_at(o["y"], 0.0) + r * std::sin(a));
    }
  }
}
}  // namespace

double unit_draw(std::uint64_t key) {
  return double(splitmix64(key) >> 11) * 0x1.0p-53;
}

std::uint64_t draw_key(std::uint64_t seed, std::uint64_t index, const std::string& name,
                       std::uint64_t k) {
  std::uint64_t x = splitmix64(seed);
  x = splitmix64(x ^ index);
  x = splitmix64(x ^ fnv1a(name));
  return splitmix64(x ^ k);
}

Variant make_variant(const CampaignSpec& spec, std::uint64_t index) {
  Variant v;
  v.index = index;
  const std::uint64_t robots = spec.robots.empty() ? 1 : spec.robots.size();
  const std::uint64_t pair = index / spec.variants;  // (scenario, robot) pair
  v.scenario = std::size_t(pair / robots);
  v.base_name = fs::path(spec.scenarios.at(v.scenario)).stem().string();
  if (!spec.robots.empty()) {
    v.preset = spec.robots[pair % robots].preset;
    v.strategy = spec.robots[pair % robots].strategy;
  }
  v.seed = splitmix64(draw_key(spec.seed, index, "seed", 0)) >> 11;
  for (const Perturbation& p : spec.perturbations) v.values.push_back(draw(spec, index, p));
  return v;
}

ScenarioText variant_scenario(const CampaignSpec& spec, const Variant& v) {
  ScenarioText r;
  const std::string& base = spec.scenarios.at(v.scenario);
  try {
    // The base as every loader reads it: size-bounded, and pre-checked so that yaml-cpp's
    // leniency (an unterminated quote swallowing the rest) cannot reach the variant.
    const std::string base_text = loader::strict::read_file(base);
    if (const std::string e = loader::strict::precheck_yaml(base_text); !e.empty()) {
      r.error = base + ":" + e;
      return r;
    }
    YAML::Node root = YAML::Load(base_text);
    if (!root.IsMap()) {
      r.error = base + ": expected a scenario (a map)";
      return r;
    }
    root["seed"] = v.seed;
    if (!v.preset.empty()) root["robot"]["preset"] = v.preset;
    if (!v.strategy.empty()) root["mission"]["strategy"] = v.strategy;
    for (std::size_t i = 0; i < spec.perturbations.size(); ++i) {
      apply(spec.perturbations[i].key, v.values[i], v, spec, root);
    }
    if (root["map"] && root["map"].IsScalar()) {
      const fs::path map = root["map"].as<std::string>();
      if (map.is_relative()) {
        root["map"] = fs::absolute(fs::path(base).parent_path() / map).lexically_normal().string();
      }
    }
    std::string head =
        "# carril campaign " + spec.name + ", variant " + std::to_string(v.index) + ": " + base;
    if (!v.preset.empty()) head += ", preset " + v.preset + ", strategy " + v.strategy;
    head += ", seed " + std::to_string(v.seed) + "\n";
    for (std::size_t i = 0; i < spec.perturbations.size(); ++i) {
      head += "#   " + spec.perturbations[i].key + " = " + text(v.values[i]) + "\n";
    }
    YAML::Emitter out;
    out << root;
    if (!out.good()) {
      r.error = base + ": writing the variant: " + out.GetLastError();
      return r;
    }
    r.text = head + out.c_str() + "\n";
    r.ok = true;
  } catch (const std::exception& e) {
    r.error = base + ": making variant " + std::to_string(v.index) + ": " + e.what();
  }
  return r;
}

}  // namespace carril::sim::campaign
