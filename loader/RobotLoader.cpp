#include "loader/RobotLoader.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string_view>

#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/control/MotionLimiter.hpp"
#include "firmware/core/Param.hpp"
#include "firmware/estimation/MclConfig.hpp"
#include "firmware/kinematics/DriveKinematics.hpp"
#include "loader/RobotSections.hpp"

namespace carril::loader {

namespace {

using strict::Node;
using strict::Range;

// Physical bounds: every accepted value gives a finite, non-degenerate simulation and a valid
// firmware configuration. docs/configuration.md lists them all.
const Range kYawDeg = Range::closed(-360.0, 360.0);
const Range kMount = Range::closed(-5.0, 5.0);  // sensor mount offsets [m]
const Range kWheelSize = Range::closed(fw::kWheelSpanMinM, fw::kWheelSpanMaxM);  // the firmware's

// Derived camera rules: the top image row looks at least this far below the horizon, and the
// optical axis meets the floor within this distance.
constexpr double kMinTopRowDepressionDeg = 1.0;
constexpr double kMaxCentreRayDistanceM = 20.0;

double deg2rad(double deg) {
  return deg * std::numbers::pi / 180.0;
}

}  // namespace

void parse_camera(const Node& m, CameraSpec& c, bool all) {
  m.expect_map({"x_m", "y_m", "z_m", "tilt_deg", "hfov_deg", "width", "height", "rate_hz",
                "noise_std", "exposure"});
  if (auto n = m.get("x_m", all)) c.x_m = n->number(kMount);
  if (auto n = m.get("y_m", all)) c.y_m = n->number(kMount);
  if (auto n = m.get("z_m", all)) c.z_m = n->number(Range::closed(0.05, 5.0));
  if (auto n = m.get("tilt_deg", all)) c.tilt_deg = n->number(Range::closed(5.0, 90.0));
  if (auto n = m.get("hfov_deg", all)) c.hfov_deg = n->number(Range::closed(20.0, 150.0));
  // The firmware's image buffer is fixed at hal::kMaxImageWidth x kMaxImageHeight.
  if (auto n = m.get("width", all)) c.width = static_cast<int>(n->integer(32, 1280));
  if (auto n = m.get("height", all)) c.height = static_cast<int>(n->integer(32, 960));
  if (auto n = m.get("rate_hz", all)) c.rate_hz = n->number(Range::closed(1.0, 240.0));
  if (auto n = m.get("noise_std", all)) c.noise_std = n->number(Range::closed(0.0, 100.0));
  // Simulated only (an over- or under-exposed image), so never required.
  if (auto n = m.get("exposure")) c.exposure = n->number(Range::closed(0.25, 4.0));
}

// The camera must see the floor: the top image row looks below the horizon (else part of the
// image has no floor and the homography's inverse degenerates) and the image centre meets the
// floor at a sane distance. `where` is the camera block that set the values.
void check_camera_view(const Node& where, const CameraSpec& c) {
  const double half_vfov_deg =
      std::atan((c.height / 2.0) / ((c.width / 2.0) / std::tan(deg2rad(c.hfov_deg / 2.0)))) *
      180.0 / std::numbers::pi;
  const double top_row_deg = c.tilt_deg - half_vfov_deg;
  if (top_row_deg < kMinTopRowDepressionDeg) {
    where.child_path("tilt_deg")
        .expected("a tilt at least " + strict::format_number(kMinTopRowDepressionDeg) +
                      " deg more than half the vertical field of view (" +
                      strict::format_number(half_vfov_deg) + " deg from hfov_deg " +
                      strict::format_number(c.hfov_deg) + ", " + std::to_string(c.width) + "x" +
                      std::to_string(c.height) + "), so the whole image sees the floor",
                  strict::format_number(c.tilt_deg));
  }
  const double centre_m = c.z_m / std::tan(deg2rad(c.tilt_deg));
  if (centre_m > kMaxCentreRayDistanceM) {
    where.child_path("tilt_deg")
        .expected("a tilt whose image centre meets the floor within " +
                      strict::format_number(kMaxCentreRayDistanceM) + " m (z_m " +
                      strict::format_number(c.z_m) +
                      " / tan(tilt_deg) = " + strict::format_number(centre_m) + " m)",
                  strict::format_number(c.tilt_deg));
  }
}

void parse_lidar(const Node& m, LidarSpec& l, bool all) {
  if (all) {
    m.expect_map({"present", "x_m", "y_m", "yaw_deg", "fov_deg", "beams", "range_min_m",
                  "range_max_m", "reliable_range_m", "rate_hz", "noise_std_m", "dropout"});
    if (auto n = m.get("present")) l.present = n->boolean();
    // A lidar that is not fitted needs no mount: its other keys become optional.
    all = l.present;
  } else {
    m.expect_map({"x_m", "y_m", "yaw_deg", "fov_deg", "beams", "range_min_m", "range_max_m",
                  "reliable_range_m", "rate_hz", "noise_std_m", "dropout"});
  }
  if (auto n = m.get("x_m", all)) l.x_m = n->number(kMount);
  if (auto n = m.get("y_m", all)) l.y_m = n->number(kMount);
  if (auto n = m.get("yaw_deg", all)) l.yaw_deg = n->number(kYawDeg);
  if (auto n = m.get("fov_deg", all)) l.fov_deg = n->number(Range::closed(1.0, 360.0));
  // hal::kMaxScanBeams.
  if (auto n = m.get("beams", all)) l.beams = static_cast<int>(n->integer(2, 2048));
  const auto max_n = m.get("range_max_m", all);
  const auto min_n = m.get("range_min_m", all);
  if (max_n) l.range_max_m = max_n->number(Range::closed(0.5, 100.0));
  if (min_n) {
    l.range_min_m = min_n->number(Range::closed(0.0, 10.0));
    if (l.range_min_m >= l.range_max_m) {
      min_n->expected("a number in [0, range_max_m = " + strict::format_number(l.range_max_m) + ")",
                      min_n->raw());
    }
  } else if (max_n && l.range_max_m <= l.range_min_m) {
    max_n->expected("a number in (range_min_m = " + strict::format_number(l.range_min_m) + ", 100]",
                    max_n->raw());
  }
  // Optional: what the datasheet says it detects reliably (a dark target), at most its range.
  if (auto n = m.get("reliable_range_m")) {
    l.reliable_range_m = n->number(Range::closed(0.0, 100.0));
    if (l.reliable_range_m > l.range_max_m ||
        (l.reliable_range_m > 0.0 && l.reliable_range_m <= l.range_min_m)) {
      n->expected("a number in (range_min_m = " + strict::format_number(l.range_min_m) +
                      ", range_max_m = " + strict::format_number(l.range_max_m) + "]",
                  n->raw());
    }
  }
  if (auto n = m.get("rate_hz", all)) l.rate_hz = n->number(Range::closed(1.0, 100.0));
  if (auto n = m.get("noise_std_m", all)) l.noise_std_m = n->number(Range::closed(0.0, 1.0));
  // Simulated only (beams lost to dark or shiny surfaces), so never required.
  if (auto n = m.get("dropout")) l.dropout = n->number(Range::closed(0.0, 0.9));
}

// The same bounds as sim::Lidar3dConfig::validate() (host_sim/sensors/Lidar3dSim.cpp).
void parse_lidar3d(const Node& m, Lidar3dSpec& l, bool all) {
  if (all) {
    m.expect_map({"present", "x_m", "y_m", "z_m", "yaw_deg", "rings", "vertical_min_deg",
                  "vertical_max_deg", "azimuths", "rate_hz", "range_min_m", "range_max_m",
                  "noise_std_m", "drop_probability"});
    // The block being there means fitted, unless it says `present: false`; then the rest is
    // optional.
    l.present = true;
    if (auto n = m.get("present")) l.present = n->boolean();
    all = l.present;
  } else {
    m.expect_map({"x_m", "y_m", "z_m", "yaw_deg", "rings", "vertical_min_deg", "vertical_max_deg",
                  "azimuths", "rate_hz", "range_min_m", "range_max_m", "noise_std_m",
                  "drop_probability"});
  }
  if (auto n = m.get("x_m", all)) l.x_m = n->number(kMount);
  if (auto n = m.get("y_m", all)) l.y_m = n->number(kMount);
  if (auto n = m.get("z_m", all)) l.z_m = n->number(Range::closed(0.05, 5.0));
  if (auto n = m.get("yaw_deg", all)) l.yaw_deg = n->number(kYawDeg);
  // rings x azimuths fits hal::kMaxCloudPoints (65536).
  if (auto n = m.get("rings", all)) l.rings = static_cast<int>(n->integer(1, 128));
  const auto az_n = m.get("azimuths", all);
  if (az_n) l.azimuths = static_cast<int>(az_n->integer(1, 65536));
  if (l.rings * l.azimuths > 65536) {
    (az_n ? *az_n : m)
        .expected("rings x azimuths at most 65536 (hal::kMaxCloudPoints); rings " +
                      std::to_string(l.rings) + " x azimuths " + std::to_string(l.azimuths),
                  std::to_string(l.rings * l.azimuths));
  }
  if (auto n = m.get("vertical_min_deg", all))
    l.vertical_min_deg = n->number(Range::closed(-90.0, 90.0));
  const auto vmax_n = m.get("vertical_max_deg", all);
  if (vmax_n) l.vertical_max_deg = vmax_n->number(Range::closed(-90.0, 90.0));
  if (l.rings > 1 && l.vertical_max_deg <= l.vertical_min_deg) {
    (vmax_n ? *vmax_n : m)
        .expected("a number in (vertical_min_deg = " + strict::format_number(l.vertical_min_deg) +
                      ", 90]",
                  strict::format_number(l.vertical_max_deg));
  }
  if (auto n = m.get("rate_hz", all)) l.rate_hz = n->number(Range::closed(1.0, 100.0));
  const auto max_n = m.get("range_max_m", all);
  const auto min_n = m.get("range_min_m", all);
  if (max_n) l.range_max_m = max_n->number(Range::closed(0.5, 200.0));
  if (min_n) l.range_min_m = min_n->number(Range::closed(0.0, 10.0));
  if (l.range_min_m >= l.range_max_m) {
    (min_n   ? *min_n
     : max_n ? *max_n
             : m)
        .expected("range_min_m below range_max_m = " + strict::format_number(l.range_max_m),
                  strict::format_number(l.range_min_m));
  }
  if (auto n = m.get("noise_std_m", all)) l.noise_std_m = n->number(Range::closed(0.0, 1.0));
  if (auto n = m.get("drop_probability", all)) {
    l.drop_probability = n->number(Range::closed(0.0, 1.0));
  }
}

// The range the firmware's settings table declares for `name` of Cfg, declared once there. A row
// that is not there is a programming error of this file (every shipped robot file would fail).
template <class Cfg>
Range firmware_range(std::string_view name) {
  for (const fw::Param<Cfg>& p : Cfg::params()) {
    if (name == p.info.name) return Range::closed(p.info.min, p.info.max);
  }
  throw std::logic_error("RobotLoader: no firmware settings row " + std::string(name));
}

// The robot's motion limits take their ranges from the firmware's table (MotionLimits::params());
// the wheels' acceleration is the simulator's drive model only.
void parse_limits(const Node& m, LimitsSpec& l, bool all) {
  m.expect_map({"max_speed_mps", "max_yaw_rate_radps", "max_accel_mps2", "max_wheel_speed_radps",
                "max_wheel_accel_radps2"});
  auto get = [&](const char* key, double& out) {
    if (auto n = m.get(key, all)) out = n->number(firmware_range<fw::MotionLimits>(key));
  };
  get("max_speed_mps", l.max_speed_mps);
  get("max_yaw_rate_radps", l.max_yaw_rate_radps);
  get("max_accel_mps2", l.max_accel_mps2);
  get("max_wheel_speed_radps", l.max_wheel_speed_radps);
  if (auto n = m.get("max_wheel_accel_radps2", all)) {
    l.max_wheel_accel_radps2 = n->number(Range::closed(0.5, 5000.0));
  }
}

// Bounds that keep the terrain checks meaningful: 60 deg is beyond any wheeled base, a step of
// 1 m beyond any wheel this loader accepts (radius <= 1 m).
void parse_traversability(const Node& m, TraversabilitySpec& t, bool all) {
  m.expect_map({"max_slope_deg", "max_step_up_m", "max_step_down_m"});
  if (auto n = m.get("max_slope_deg", all)) t.max_slope_deg = n->number(Range::closed(0.0, 60.0));
  if (auto n = m.get("max_step_up_m", all)) t.max_step_up_m = n->number(Range::closed(0.0, 1.0));
  if (auto n = m.get("max_step_down_m", all)) {
    t.max_step_down_m = n->number(Range::closed(0.0, 1.0));
  }
}

// Physical limits of the machine on rough ground (the simulator's terrain physics).
void parse_terrain_limits(const Node& m, TerrainLimitsSpec& t, bool all) {
  m.expect_map({"max_slope_deg", "max_step_up_m", "max_step_down_m"});
  if (auto n = m.get("max_slope_deg", all)) t.max_slope_deg = n->number(Range::closed(1.0, 60.0));
  if (auto n = m.get("max_step_up_m", all)) t.max_step_up_m = n->number(Range::closed(0.005, 1.0));
  if (auto n = m.get("max_step_down_m", all)) {
    t.max_step_down_m = n->number(Range::closed(0.005, 2.0));
  }
}

namespace {

// One field of the localisation model: its range is the firmware's own (MclConfig::validate()),
// checked here so that the error names this file, line and key.
void model_field(const Node& m, const char* key, std::optional<double>& out,
                 double fw::MclConfig::*field) {
  auto n = m.get(key);
  if (!n) return;
  fw::MclConfig c;
  c.*field = n->number();
  if (const fw::Status s = c.validate(); !s) {
    // The firmware's message begins with its own name of the field; the node names this key.
    const std::string text = s.message();
    const std::size_t colon = text.find(": ");
    n->fail(colon == std::string::npos ? text : text.substr(colon + 2));
  }
  out = c.*field;
}

void parse_localisation_model(const Node& m, LocalisationModelSpec& l) {
  m.expect_map({"sigma_hit_m", "beam_correlation", "alpha1", "alpha2", "alpha3", "alpha4",
                "surface_distance", "search_sigma_hit_m", "search_beam_correlation"});
  model_field(m, "sigma_hit_m", l.sigma_hit_m, &fw::MclConfig::sigma_hit_m);
  model_field(m, "beam_correlation", l.beam_correlation, &fw::MclConfig::beam_correlation);
  model_field(m, "alpha1", l.alpha1, &fw::MclConfig::alpha1);
  model_field(m, "alpha2", l.alpha2, &fw::MclConfig::alpha2);
  model_field(m, "alpha3", l.alpha3, &fw::MclConfig::alpha3);
  model_field(m, "alpha4", l.alpha4, &fw::MclConfig::alpha4);
  if (auto n = m.get("surface_distance")) l.surface_distance = n->boolean();
  model_field(m, "search_sigma_hit_m", l.search_sigma_hit_m, &fw::MclConfig::search_sigma_hit_m);
  model_field(m, "search_beam_correlation", l.search_beam_correlation,
              &fw::MclConfig::search_beam_correlation);
}

RobotSpec parse_preset(const Node& root) {
  root.expect_map({"name", "drive", "body", "wheels", "cruise_speed_mps", "control_rate_hz",
                   "camera", "lidar", "imu", "limits", "traversability", "terrain_limits",
                   "lidar3d", "localisation"});
  RobotSpec r;
  r.preset = strict::parse_name(root.at("name"));
  r.drive = root.at("drive").one_of({"mecanum", "differential"}) == "mecanum"
                ? DriveType::Mecanum
                : DriveType::Differential;
  const Node body = root.at("body");
  body.expect_map({"length_m", "width_m", "mass_kg", "shape"});
  r.length_m = body.at("length_m").number(firmware_range<fw::FirmwareConfig>("footprint_length_m"));
  r.width_m = body.at("width_m").number(firmware_range<fw::FirmwareConfig>("footprint_width_m"));
  r.mass_kg = body.at("mass_kg").number(Range::closed(1.0, 5000.0));
  if (auto n = body.get("shape")) {
    r.round_body = n->one_of({"box", "round"}) == "round";
    // A disc's footprint is the square round it: one diameter both ways.
    if (r.round_body && r.length_m != r.width_m) {
      n->fail("a round body needs length_m equal to width_m (its diameter)");
    }
  }
  const Node wheels = root.at("wheels");
  wheels.expect_map({"radius_m", "wheelbase_m", "track_m"});
  r.wheel_radius_m =
      wheels.at("radius_m").number(Range::closed(fw::kWheelRadiusMinM, fw::kWheelRadiusMaxM));
  r.wheelbase_m = wheels.at("wheelbase_m").number(kWheelSize);
  r.track_m = wheels.at("track_m").number(kWheelSize);
  r.control_rate_hz =
      root.at("control_rate_hz").number(firmware_range<fw::FirmwareConfig>("control_rate_hz"));
  const Node camera = root.at("camera");
  parse_camera(camera, r.camera, true);
  check_camera_view(camera, r.camera);
  parse_lidar(root.at("lidar"), r.lidar, true);
  if (auto l3 = root.get("lidar3d")) parse_lidar3d(*l3, r.lidar3d, true);
  if (auto imu = root.get("imu")) {
    imu->expect_map({"present", "gyro_heading", "gyro_noise_std_radps", "gyro_bias_radps"});
    r.imu.present = imu->at("present").boolean();
    if (auto g = imu->get("gyro_heading")) r.imu.gyro_heading = g->boolean();
    // Simulated only, so never required.
    if (auto n = imu->get("gyro_noise_std_radps"))
      r.imu.gyro_noise_std_radps = n->number(Range::closed(0.0, 1.0));
    if (auto n = imu->get("gyro_bias_radps"))
      r.imu.gyro_bias_radps = n->number(Range::closed(-0.5, 0.5));
  }
  parse_limits(root.at("limits"), r.limits, true);
  parse_traversability(root.at("traversability"), r.traversability, true);
  parse_terrain_limits(root.at("terrain_limits"), r.terrain_limits, true);
  if (auto l = root.get("localisation")) parse_localisation_model(*l, r.localisation);
  const Node cruise = root.at("cruise_speed_mps");
  r.cruise_speed_mps = cruise.number(Range::closed(0.01, 5.0));
  if (r.cruise_speed_mps > r.limits.max_speed_mps) {
    cruise.expected("a number in (0, limits.max_speed_mps = " +
                        strict::format_number(r.limits.max_speed_mps) + "]",
                    cruise.raw());
  }
  return r;
}

}  // namespace

RobotSpec read_robot_file(const std::string& path) {
  const std::string text = strict::read_file(path);
  RobotSpec r = parse_preset(strict::parse_document(text, &path));
  r.source_path = path;
  return r;
}

bool load_robot_preset(const std::string& path, RobotSpec& out, std::string& error) {
  RobotSpec spec;
  if (!strict::guarded(path, error, [&] { spec = read_robot_file(path); })) return false;
  out = spec;
  return true;
}

}  // namespace carril::loader
