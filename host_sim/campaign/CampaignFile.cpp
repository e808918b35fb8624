#include "host_sim/campaign/CampaignFile.hpp"

#include <filesystem>

#include "loader/StrictYaml.hpp"

namespace carril::sim::campaign {

namespace {
using loader::strict::Node;
using loader::strict::Range;
namespace fs = std::filesystem;

constexpr std::uint64_t kMaxVariants = 1000000;

const PerturbationKind* find_kind(const std::string& key) {
  for (const PerturbationKind& k : perturbation_kinds()) {
    if (key == k.key) return &k;
  }
  return nullptr;
}

std::string kind_keys() {
  std::string s;
  for (const PerturbationKind& k : perturbation_kinds())
    s += (s.empty() ? "" : ", ") + std::string(k.key);
  return s;
}

// [lo, hi] as a two-number list, lo <= hi, both within `r`.
void interval(const Node& n, const Range& r, double& lo, double& hi) {
  const std::vector<Node> v = n.items(2);
  if (v.size() != 2) n.expected("a list [low, high]");
  lo = v[0].number(r);
  hi = v[1].number(r);
  if (lo > hi) n.expected("low <= high", n.raw() + " (" + v[0].raw() + " > " + v[1].raw() + ")");
}

Distribution parse_distribution(const Node& n, const PerturbationKind& k) {
  const Range accepted = Range::closed(k.lo, k.hi);
  n.expect_map({"fixed", "uniform", "normal", "clip"});
  const auto fixed = n.get("fixed"), uniform = n.get("uniform"), normal = n.get("normal");
  if (int(fixed.has_value()) + int(uniform.has_value()) + int(normal.has_value()) != 1) {
    n.expected("exactly one of fixed, uniform, normal");
  }
  Distribution d;
  const auto clip = n.get("clip");
  if (clip && !normal) clip->expected("no clip (only a normal distribution takes one)", "clip");
  if (fixed) {
    d.kind = Distribution::Kind::Fixed;
    d.a = d.b = fixed->number(accepted);
  } else if (uniform) {
    d.kind = Distribution::Kind::Uniform;
    interval(*uniform, accepted, d.a, d.b);
  } else {
    d.kind = Distribution::Kind::Normal;
    const std::vector<Node> v = normal->items(2);
    if (v.size() != 2) normal->expected("a list [mean, standard deviation]");
    d.a = v[0].number(accepted);
    d.b = v[1].number(Range::non_negative());
    // Without a clip a normal reaches any value: the key's accepted range must bound it.
    if (!clip) n.child_path("clip").expected("[low, high] within " + accepted.describe(), "none");
    interval(*clip, accepted, d.clip_lo, d.clip_hi);
    if (d.a < d.clip_lo || d.a > d.clip_hi) {
      clip->expected("an interval holding the mean " + v[0].raw(), clip->raw());
    }
  }
  return d;
}

RobotStrategy parse_robot(const Node& n) {
  n.expect_map({"preset", "strategy"});
  RobotStrategy r;
  r.preset = loader::strict::parse_name(n.at("preset"));
  r.strategy = n.at("strategy").one_of({"line_priority", "marks", "pid"});
  return r;
}

void parse(const Node& root, CampaignSpec& s) {
  root.expect_map(
      {"name", "description", "seed", "scenarios", "robots", "variants", "perturbations"});
  s.name = loader::strict::parse_name(root.at("name"));
  if (auto d = root.get("description")) (void)d->string();
  if (auto n = root.get("seed")) s.seed = n->unsigned_integer();
  const fs::path base = fs::path(s.path).parent_path();
  const Node list = root.at("scenarios");
  for (const Node& item : list.items(1)) {
    const std::string file = item.string();
    if (file.empty()) item.expected("a scenario file");
    const fs::path p =
        (fs::path(file).is_absolute() ? fs::path(file) : base / file).lexically_normal();
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) item.expected("a readable scenario file", p.string());
    s.scenarios.push_back(p.string());
  }
  if (s.scenarios.size() > 256)
    list.expected("at most 256 scenarios", std::to_string(s.scenarios.size()));
  if (auto n = root.get("robots")) {
    for (const Node& item : n->items(1)) s.robots.push_back(parse_robot(item));
    if (s.robots.size() > 64)
      n->expected("at most 64 robot/strategy pairs", std::to_string(s.robots.size()));
  }
  s.variants = std::uint32_t(root.at("variants").integer(1, std::int64_t(kMaxVariants)));
  if (s.variant_count() > kMaxVariants) {
    root.at("variants")
        .expected("at most " + std::to_string(kMaxVariants) +
                      " variants in all (scenarios x robots x variants)",
                  std::to_string(s.variant_count()));
  }
  if (auto p = root.get("perturbations")) {
    if (p->yaml().IsMap()) {
      std::vector<std::string> keys;
      for (const PerturbationKind& k : perturbation_kinds()) keys.emplace_back(k.key);
      p->expect_map(keys);
    } else if (!p->yaml().IsNull()) {
      p->expected("a map of perturbations (" + kind_keys() + ")");
    }
    // In the fixed order of perturbation_kinds(): the CSV's columns do not depend on the file's.
    for (const PerturbationKind& k : perturbation_kinds()) {
      if (!p->yaml().IsMap()) break;
      if (auto n = p->get(k.key)) s.perturbations.push_back({k.key, parse_distribution(*n, k)});
    }
  }
}
}  // namespace

const std::vector<PerturbationKind>& perturbation_kinds() {
  static const std::vector<PerturbationKind> kinds = {
      {"start_offset_m", -1.0, 1.0, "m", "robot.start moved sideways (+ left of its heading)"},
      {"start_heading_deg", -45.0, 45.0, "deg", "added to robot.start.yaw_deg"},
      {"camera_noise", 0.0, 100.0, "grey levels", "robot.camera.noise_std"},
      {"lidar_noise_m", 0.0, 1.0, "m", "robot.lidar.noise_std_m"},
      {"wheel_slip", 0.0, 0.5, "-", "odometry.slip"},
      {"wheel_radius_error", -0.2, 0.2, "-", "odometry.wheel_radius_error"},
      {"obstacle_jitter_m", 0.0, 2.0, "m",
       "every obstacle moved by up to this, uniformly in a disc"},
      {"extra_obstacles", 0.0, 20.0, "obstacles",
       "this many more cylinders (rounded), placed at random off the tape, the start and the "
       "walls"},
      {"tape_gaps_per_m", 0.0, 5.0, "1/m", "tape_wear.gaps_per_m"},
      {"tape_gap_length_m", 0.005, 2.0, "m", "tape_wear.gap_length_m"},
      {"tape_fade", 0.0, 1.0, "-", "tape_wear.fade"},
      {"floor_brightness", 0.5, 1.5, "-", "floor.color times this (each channel at most 255)"},
      {"floor_speckle", 0.0, 0.3, "-", "floor.speckle"},
      {"camera_exposure", 0.25, 4.0, "-", "robot.camera.exposure"},
      {"glare_intensity", 0.0, 255.0, "grey levels", "glare.intensity"},
      {"lidar_dropout", 0.0, 0.9, "-", "robot.lidar.dropout"},
  };
  return kinds;
}

std::uint64_t CampaignSpec::variant_count() const {
  return std::uint64_t(scenarios.size()) * std::uint64_t(robots.empty() ? 1 : robots.size()) *
         std::uint64_t(variants);
}

CampaignLoad load_campaign_text(const std::string& text, const std::string& path) {
  CampaignLoad r;
  r.spec.path = path;
  r.ok = loader::strict::guarded(path, r.error, [&] {
    const Node root = loader::strict::parse_document(text, &r.spec.path);
    parse(root, r.spec);
  });
  if (!r.ok) r.spec = CampaignSpec{};
  return r;
}

CampaignLoad load_campaign(const std::string& path) {
  std::string text;
  std::string error;
  if (!loader::strict::guarded(path, error, [&] { text = loader::strict::read_file(path); })) {
    return CampaignLoad{false, {}, error};
  }
  return load_campaign_text(text, path);
}

}  // namespace carril::sim::campaign
