#include "host_sim/app/HilRun.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <ctime>
#include <sstream>

#include "hal/can/Candump.hpp"

namespace carril::sim {

namespace {
constexpr double kStillRadps = 0.01;  // a wheel slower than this stands still [rad/s]

hal::TimeNs to_ns(double s) {
  return static_cast<hal::TimeNs>(std::llround(s * 1e9));
}

const char* state_code(hal::cia402::State s) {
  using S = hal::cia402::State;
  switch (s) {
    case S::NotReadyToSwitchOn:
      return "NR";
    case S::SwitchOnDisabled:
      return "SD";
    case S::ReadyToSwitchOn:
      return "RS";
    case S::SwitchedOn:
      return "SO";
    case S::OperationEnabled:
      return "OE";
    case S::QuickStopActive:
      return "QS";
    case S::FaultReactionActive:
      return "FR";
    case S::Fault:
      return "F";
    case S::Unknown:
      break;
  }
  return "?";
}

bool parse_int(const std::string& s, int base, long& out) {
  const char* b = s.data();
  const char* e = b + s.size();
  if (base == 16 && s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) b += 2;
  const auto [p, ec] = std::from_chars(b, e, out, base);
  return b != e && ec == std::errc{} && p == e;
}
}  // namespace

bool parse_injection(const std::string& text, int wheels, HilInjection& out, std::string& why) {
  HilInjection inj;
  inj.text = text;
  const auto c1 = text.find(':');
  const auto c2 = c1 == std::string::npos ? c1 : text.find(':', c1 + 1);
  if (c2 == std::string::npos) {
    why = "expected T:DRIVE:WHAT (e.g. 20:1:heartbeat_silence), got \"" + text + "\"";
    return false;
  }
  const std::string t = text.substr(0, c1), d = text.substr(c1 + 1, c2 - c1 - 1),
                    w = text.substr(c2 + 1);
  char* end = nullptr;
  inj.t_s = std::strtod(t.c_str(), &end);
  if (t.empty() || *end != '\0' || !std::isfinite(inj.t_s) || inj.t_s < 0.0) {
    why = "time: expected seconds >= 0, got \"" + t + "\"";
    return false;
  }
  long v = 0;
  if (d == "all") {
    inj.drive = -1;
  } else if (parse_int(d, 10, v) && v >= 0 && v < wheels) {
    inj.drive = static_cast<int>(v);
  } else {
    why = "drive: expected a wheel index 0 to " + std::to_string(wheels - 1) + " or all, got \"" +
          d + "\"";
    return false;
  }
  const auto colon = w.find(':');
  const std::string kind = w.substr(0, colon);
  const std::string arg = colon == std::string::npos ? "" : w.substr(colon + 1);
  using What = HilInjection::What;
  if (kind == "heartbeat_silence" && arg.empty()) {
    inj.what = What::HeartbeatSilence;
  } else if (kind == "bus_silence" && arg.empty()) {
    inj.what = What::BusSilence;
  } else if (kind == "refuse_enable" && arg.empty()) {
    inj.what = What::RefuseEnable;
  } else if (kind == "fault" && parse_int(arg, 16, v) && v > 0 && v <= 0xFFFF) {
    inj.what = What::Fault;
    inj.code = static_cast<std::uint16_t>(v);
  } else if ((kind == "corrupt" || kind == "unknown") && parse_int(arg, 10, v) && v > 0 &&
             v <= 100000) {
    inj.what = kind == "corrupt" ? What::Corrupt : What::Unknown;
    inj.count = static_cast<int>(v);
  } else {
    why =
        "what: expected heartbeat_silence, bus_silence, refuse_enable, fault:0xCODE, corrupt:N "
        "or unknown:N, got \"" +
        w + "\"";
    return false;
  }
  out = inj;
  return true;
}

HilRun::HilRun(const Scenario& scenario, std::uint64_t seed, hal::CanBus& wire,
               const HilConfig& cfg)
    : scenario_(scenario),
      wire_(wire),
      cfg_(cfg),
      world_(scenario),
      metrics_(scenario),
      camera_(scenario, seed),
      lidar_(scenario.robot.lidar, seed),
      gyro_(scenario.robot.imu, seed),
      drive_bus_([&] {
        hal::LoopbackCanBus::Config c;
        c.endpoints = world_.wheel_count() + 1;  // the drives, then the bridge
        c.tx_depth = 256;
        c.rx_depth = 512;
        return c;
      }()),
      scan_(std::make_unique<hal::LaserScan>()) {
  for (int i = 0; i < world_.wheel_count(); ++i) {
    DriveEmulator::Config e;
    if (std::size_t(i) < cfg_.controller.can.drives.size()) {
      const loader::ControllerDriveSpec& d = cfg_.controller.can.drives[std::size_t(i)];
      e.node = static_cast<std::uint8_t>(d.node);
      e.units = hal::cia402::DriveUnits{d.counts_per_rev, d.gear_ratio};
    } else {
      e.node = static_cast<std::uint8_t>(i + 1);
    }
    drives_.push_back(std::make_unique<DriveEmulator>(drive_bus_.endpoint(i), e));
  }
  for (const HilInjection& inj : cfg_.injections) outcomes_.push_back({&inj, false, -1.0});
}

HilRun::~HilRun() {
  scip_.stop();
}

bool HilRun::open(std::string& error) {
  if (cfg_.scip_port != 0) {
    ScipServerConfig sc;
    sc.port = cfg_.scip_port;
    lidar_.scan(world_, *scan_);  // the geometry of the scans it will serve
    const char* why = "";
    const int rpm = static_cast<int>(std::lround(60.0 * scenario_.robot.lidar.rate_hz));
    if (!ScipServer::geometry_for(*scan_, rpm, sc.geometry, why)) {
      error = std::string("lidar: not servable over SCIP 2.0: ") + why;
      return false;
    }
    if (!scip_.start(sc)) {
      error = "--scip-port " + std::to_string(cfg_.scip_port) + ": " + scip_.error();
      return false;
    }
  }
  if (!cfg_.shm_name.empty()) {
    if (!shm_.create(cfg_.shm_name.c_str())) {
      error = "--shm " + cfg_.shm_name + ": " + shm_.error();
      return false;
    }
    shm_open_ = true;
  }
  return true;
}

void HilRun::log(const hal::CanFrame& f) {
  if (cfg_.can_log == nullptr) return;
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  char line[hal::kCandumpMaxLine + 2];
  std::size_t n = hal::format_candump(f, hal::TimeNs(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec,
                                      cfg_.can_log_iface.c_str(), line, sizeof line - 1);
  line[n++] = '\n';
  std::fwrite(line, 1, n, cfg_.can_log);
}

void HilRun::bridge() {
  hal::CanBus& inside = drive_bus_.endpoint(world_.wheel_count());
  hal::CanFrame f;
  // From the controller to the drives: all that waits (the caller's bus bounds it).
  for (int k = 0; k < 1024 && wire_.receive(f); ++k) {
    ++from_wire_;
    log(f);
    if (!f.error) inside.send(f);
  }
  drive_bus_.transfer();
  // From the drives to the controller.
  while (inside.receive(f)) {
    log(f);
    if (wire_.send(f)) {
      ++to_wire_;
    } else {
      ++wire_refused_;
    }
  }
  wire_.flush();
}

void HilRun::apply_injections() {
  const double t = sim_time_s();
  for (InjectionOutcome& o : outcomes_) {
    if (o.applied || t < o.injection->t_s) continue;
    o.applied = true;
    for (int i = 0; i < wheels(); ++i) {
      if (o.injection->drive >= 0 && o.injection->drive != i) continue;
      DriveEmulator& d = *drives_[std::size_t(i)];
      using What = HilInjection::What;
      switch (o.injection->what) {
        case What::HeartbeatSilence:
          d.set_silence(DriveEmulator::Silence::Heartbeat);
          break;
        case What::BusSilence:
          d.set_silence(DriveEmulator::Silence::Bus);
          break;
        case What::Fault:
          d.inject_fault(o.injection->code);
          break;
        case What::RefuseEnable:
          d.refuse_enable(hal::cia402::State::SwitchOnDisabled);
          break;
        case What::Corrupt:
          d.inject_corrupt_frames(o.injection->count);
          break;
        case What::Unknown:
          d.inject_unknown_frames(o.injection->count);
          break;
      }
    }
    std::printf("hil: t %.2f s: injected %s\n", t, o.injection->text.c_str());
  }
}

void HilRun::publish_sensors() {
  const double t = sim_time_s();
  const hal::TimeNs t_ns = to_ns(t);
  if (shm_open_ && t >= next_cam_s_) {
    camera_.render(world_.pose(), shm_.camera_begin());
    shm_.camera_commit(t_ns);
    next_cam_s_ += 1.0 / scenario_.robot.camera.rate_hz;
  }
  if (cfg_.scip_port != 0 && t >= next_scan_s_) {
    lidar_.scan(world_, *scan_);
    scan_->stamp_ns = t_ns;
    scip_.publish(*scan_);
    next_scan_s_ += 1.0 / scenario_.robot.lidar.rate_hz;
  }
  if (shm_open_ && t >= next_imu_s_) {
    double vx = 0, vy = 0, wz = 0;
    world_.body_velocity(vx, vy, wz);
    hal::ImuSample imu;
    imu.stamp_ns = t_ns;
    imu.valid = true;
    imu.yaw_rate_radps = gyro_.read(wz);  // flat floor: roll and pitch zero
    shm_.publish_imu(imu);
    next_imu_s_ += 1.0 / scenario_.robot.control_rate_hz;
  }
}

void HilRun::step(double dt_s) {
  dt_s = std::clamp(dt_s, 1e-4, kMaxStepS);
  apply_injections();
  bridge();
  const double t = sim_time_s();
  const hal::TimeNs t_ns = to_ns(t);
  for (auto& d : drives_) d->step(t_ns, dt_s);
  bridge();
  // The wheels turn as the drives' motors do (a mirrored mounting, inverted in the controller
  // file, turns the wheel against the motor).
  float target[hal::kMaxWheels] = {};
  for (int i = 0; i < wheels(); ++i) {
    const bool inverted = std::size_t(i) < cfg_.controller.can.drives.size() &&
                          cfg_.controller.can.drives[std::size_t(i)].inverted;
    const double v = drives_[std::size_t(i)]->wheel_speed_radps();
    target[i] = static_cast<float>(inverted ? -v : v);
  }
  world_.set_wheel_targets(target);
  world_.step(dt_s);
  for (const ContactStart& c : world_.take_new_contacts()) {
    (void)c;
    metrics_.add_collision();
  }
  t_s_ += dt_s;
  TickSample s;
  s.t_s = sim_time_s();
  s.pose = world_.pose();
  world_.body_velocity(s.vx_mps, s.vy_mps, s.wz_radps);
  s.following = std::hypot(s.vx_mps, s.vy_mps) > 0.05;
  metrics_.add(s);
  publish_sensors();

  // Figures: the first SYNC, the controller's heartbeat lost, when every wheel stood still after
  // each injection and after that loss.
  if (first_sync_s_ < 0.0 && drives_[0]->counters().syncs > 0) first_sync_s_ = s.t_s;
  const bool still = max_wheel_speed() < kStillRadps;
  for (InjectionOutcome& o : outcomes_) {
    if (o.applied && o.stopped_after_s < 0.0 && still) o.stopped_after_s = s.t_s - o.injection->t_s;
  }
  if (master_lost_at_s_ < 0.0) {
    for (auto& d : drives_) {
      if (d->master_heartbeat_lost()) master_lost_at_s_ = s.t_s;
    }
  }
  if (master_lost_at_s_ >= 0.0 && stopped_after_master_s_ < 0.0 && still) {
    stopped_after_master_s_ = s.t_s - master_lost_at_s_;
  }
}

double HilRun::max_wheel_speed() const {
  double m = 0.0;
  for (const auto& d : drives_) m = std::max(m, std::fabs(d->wheel_speed_radps()));
  return m;
}

double HilRun::sync_rate_hz() const {
  if (first_sync_s_ < 0.0) return 0.0;
  const double span = sim_time_s() - first_sync_s_;
  return span > 0.0 ? double(drives_[0]->counters().syncs) / span : 0.0;
}

double HilRun::tpdo_rate_hz() const {
  if (first_sync_s_ < 0.0) return 0.0;
  const double span = sim_time_s() - first_sync_s_;
  std::uint64_t n = 0;
  for (const auto& d : drives_) n += d->counters().tpdos_sent;
  return span > 0.0 ? double(n) / span : 0.0;
}

std::string HilRun::status_line() const {
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(1);
  o << "hil: t " << sim_time_s() << " s: laps " << metrics_.laps() << ", progress ";
  o.precision(2);
  o << metrics_.progress() << "; drives";
  for (const auto& d : drives_) o << ' ' << state_code(d->state());
  o << "; wheels";
  o.precision(1);
  for (const auto& d : drives_) o << ' ' << d->wheel_speed_radps();
  o << " rad/s; sync " << sync_rate_hz() << " Hz, tpdo " << tpdo_rate_hz() << " /s";
  if (master_lost_at_s_ >= 0.0) o << "; controller heartbeat lost";
  return o.str();
}

std::string HilRun::summary_json() const {
  std::ostringstream o;
  o.precision(6);
  o << "{\n  \"scenario\": \"" << scenario_.name << "\",\n";
  o << "  \"sim_time_s\": " << sim_time_s() << ",\n";
  o << "  \"laps\": " << metrics_.laps() << ",\n";
  o << "  \"progress\": " << metrics_.progress() << ",\n";
  o << "  \"collisions\": " << metrics_.collisions() << ",\n";
  o << "  \"path_length_m\": " << metrics_.path_length_m() << ",\n";
  o << "  \"cross_track_rms_m\": " << metrics_.cross_track_rms_m() << ",\n";
  o << "  \"frames_from_controller\": " << from_wire_ << ",\n";
  o << "  \"frames_to_controller\": " << to_wire_ << ",\n";
  o << "  \"frames_refused\": " << wire_refused_ << ",\n";
  o << "  \"sync_rate_hz\": " << sync_rate_hz() << ",\n";
  o << "  \"tpdo_rate_hz\": " << tpdo_rate_hz() << ",\n";
  o << "  \"controller_heartbeat_lost_at_s\": " << master_lost_at_s_ << ",\n";
  o << "  \"stopped_after_controller_lost_s\": " << stopped_after_master_s_ << ",\n";
  o << "  \"drives\": [";
  for (std::size_t i = 0; i < drives_.size(); ++i) {
    const DriveEmulator& d = *drives_[i];
    const DriveEmulator::Counters& c = d.counters();
    o << (i ? ",\n" : "\n") << "    {\"node\": " << int(d.config().node) << ", \"state\": \""
      << hal::cia402::state_name(d.state()) << "\", \"error_code\": " << d.error_code()
      << ", \"master_heartbeat_lost\": " << (d.master_heartbeat_lost() ? "true" : "false")
      << ", \"syncs\": " << c.syncs << ", \"tpdos\": " << c.tpdos_sent
      << ", \"rpdos\": " << c.rpdos_applied << ", \"sdo_requests\": " << c.sdo_requests
      << ", \"faults\": " << c.faults << ", \"wheel_radps\": " << d.wheel_speed_radps() << "}";
  }
  o << "\n  ],\n  \"injections\": [";
  for (std::size_t i = 0; i < outcomes_.size(); ++i) {
    const InjectionOutcome& x = outcomes_[i];
    o << (i ? ",\n" : "\n") << "    {\"what\": \"" << x.injection->text
      << "\", \"applied\": " << (x.applied ? "true" : "false")
      << ", \"stopped_after_s\": " << x.stopped_after_s << "}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

}  // namespace carril::sim
