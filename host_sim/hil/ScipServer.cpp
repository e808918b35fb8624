#include "host_sim/hil/ScipServer.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>

namespace carril::sim {

namespace scip = hal::scip;

namespace {

// The server thread sleeps in poll() until the client writes, a scan is published, a fault is
// injected or stop() is called (each wakes it through wake_fd_); this bound is only a backstop.
// A poll every 2 ms instead cost a system call each, 75 us apiece under user-mode-linux.
constexpr int kPollMs = 100;
constexpr std::size_t kMaxIn = 4096;

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

bool is_stream(scip::Command c) {
  return c == scip::Command::MD || c == scip::Command::MS || c == scip::Command::ME;
}

void int_text(int v, char* out, std::size_t cap) {
  std::snprintf(out, cap, "%d", v);
}

}  // namespace

ScipServer::ScipServer() = default;

ScipServer::~ScipServer() {
  stop();
}

bool ScipServer::geometry_for(const hal::LaserScan& shape, int scan_rpm, scip::Geometry& g,
                              const char*& why) {
  const double inc = double(shape.angle_increment_rad);
  if (!std::isfinite(inc) || !std::isgreater(inc, 0.0) || shape.count == 0)
    return why = "scan has no beams or no positive angle increment", false;
  const double ares = 2.0 * M_PI / inc;
  const double first = -double(shape.angle_min_rad) / inc;  // steps from the first beam to front
  if (std::fabs(ares - std::round(ares)) > 1e-3 || std::fabs(first - std::round(first)) > 1e-3)
    return why = "beams are not whole steps of a full turn (2 pi / increment not an integer)",
           false;
  g = scip::Geometry{};
  g.ares = int(std::lround(ares));
  g.afrt = int(std::lround(first));
  g.amin = 0;
  g.amax = shape.count - 1;
  if (g.afrt < 0 || g.afrt > g.amax) return why = "the front (0 rad) is outside the scan", false;
  g.dmin_mm = int(std::lround(double(shape.range_min_m) * 1000.0));
  g.dmax_mm = int(std::lround(double(shape.range_max_m) * 1000.0));
  if (g.dmin_mm <= int(scip::kCodeInvalid)) g.dmin_mm = int(scip::kCodeInvalid) + 1;
  g.scan_rpm = scan_rpm;
  if (!g.complete()) return why = "range limits or scan rate not valid", false;
  return true;
}

bool ScipServer::start(const ScipServerConfig& cfg) {
  if (running_) return false;
  if (!cfg.geometry.complete() || cfg.geometry.dmin_mm <= int(scip::kCodeInvalid) ||
      cfg.geometry.amax - cfg.geometry.amin + 1 > hal::kMaxScanBeams) {
    std::snprintf(error_, sizeof error_,
                  "SCIP server: geometry incomplete or inconsistent (DMIN %d, DMAX %d, ARES %d, "
                  "AMIN %d, AMAX %d, AFRT %d, SCAN %d)",
                  cfg.geometry.dmin_mm, cfg.geometry.dmax_mm, cfg.geometry.ares, cfg.geometry.amin,
                  cfg.geometry.amax, cfg.geometry.afrt, cfg.geometry.scan_rpm);
    return false;
  }
  cfg_ = cfg;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(cfg.port);
  if (inet_pton(AF_INET, cfg.bind_address, &addr.sin_addr) != 1) {
    std::snprintf(error_, sizeof error_, "SCIP server: bind address '%s' is not IPv4 dotted",
                  cfg.bind_address);
    return false;
  }
  listen_fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int one = 1;
  setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  socklen_t len = sizeof addr;
  if (listen_fd_ < 0 || bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
      listen(listen_fd_, 4) != 0 ||
      getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
    std::snprintf(error_, sizeof error_, "SCIP server: cannot listen on %s:%u: %s",
                  cfg.bind_address, unsigned(cfg.port), std::strerror(errno));
    if (listen_fd_ >= 0) close(listen_fd_);
    listen_fd_ = -1;
    return false;
  }
  port_ = ntohs(addr.sin_port);
  in_.assign(kMaxIn, 0);
  values_.assign(std::size_t(hal::kMaxScanBeams) * 2, 0);
  out_.assign(std::size_t(hal::kMaxScanBeams) * 7 + 1024, 0);
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) {
    std::snprintf(error_, sizeof error_, "SCIP server: eventfd: %s", std::strerror(errno));
    close(listen_fd_);
    listen_fd_ = -1;
    return false;
  }
  start_ns_ = monotonic_ns();
  stop_ = false;
  error_[0] = '\0';
  thread_ = std::thread([this] { loop(); });
  running_ = true;
  return true;
}

void ScipServer::stop() {
  if (!running_) return;
  stop_ = true;
  wake();
  thread_.join();
  close_client();
  close(listen_fd_);
  listen_fd_ = -1;
  close(wake_fd_);
  wake_fd_ = -1;
  running_ = false;
}

void ScipServer::publish(const hal::LaserScan& scan) {
  if (int(scan.count) != cfg_.geometry.amax - cfg_.geometry.amin + 1) {
    shape_mismatches_.fetch_add(1);
    return;
  }
  scans_.write_slot() = scan;
  scans_.publish();
  wake();
}

void ScipServer::wake() {
  const std::uint64_t one = 1;
  if (wake_fd_ >= 0) (void)!write(wake_fd_, &one, sizeof one);
}

void ScipServer::inject(ScipServerFault f, int count) {
  fault_count_ = count;
  fault_ = int(f);
  wake();
}

std::uint32_t ScipServer::now_ms() const {
  return std::uint32_t((monotonic_ns() - start_ns_) / 1'000'000) & scip::max_encodable(4);
}

void ScipServer::close_client() {
  if (client_fd_ >= 0) close(client_fd_);
  client_fd_ = -1;
  streaming_ = false;
  get_pending_ = false;
  laser_on_ = false;
}

bool ScipServer::send_all(const char* data, std::size_t n) {
  while (n > 0) {
    const ssize_t k = send(client_fd_, data, n, MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    data += k;
    n -= std::size_t(k);
  }
  return true;
}

void ScipServer::loop() {
  while (!stop_) {
    if (client_fd_ < 0) {
      pollfd p{listen_fd_, POLLIN, 0};
      if (poll(&p, 1, 20) <= 0) continue;
      client_fd_ = accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
      if (client_fd_ < 0) continue;
      const int one = 1;
      setsockopt(client_fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
      timeval tv{0, 200'000};  // a client that stops reading is dropped, not waited for
      setsockopt(client_fd_, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
      clients_.fetch_add(1);
    }
    serve_client();
  }
}

// Serves the connected client until it leaves, an error or stop().
void ScipServer::serve_client() {
  std::size_t have = 0;
  while (!stop_ && client_fd_ >= 0) {
    if (fault_.load() == int(ScipServerFault::Disconnect)) {
      fault_ = int(ScipServerFault::None);
      close_client();
      return;
    }
    pollfd p[2] = {{client_fd_, POLLIN, 0}, {wake_fd_, POLLIN, 0}};
    const int r = poll(p, 2, kPollMs);
    if (r > 0 && (p[1].revents & POLLIN) != 0) {
      std::uint64_t n = 0;
      (void)!read(wake_fd_, &n, sizeof n);  // cleared; what woke us is looked at below
    }
    if (r > 0 && (p[0].revents & (POLLIN | POLLHUP | POLLERR)) != 0) {
      const ssize_t k = recv(client_fd_, in_.data() + have, in_.size() - have, 0);
      if (k <= 0) {
        close_client();
        return;
      }
      have += std::size_t(k);
      // Commands end with LF, CR or both.
      std::size_t start = 0;
      for (std::size_t i = 0; i < have; ++i) {
        if (in_[i] != '\n' && in_[i] != '\r') continue;
        if (i > start && !handle_line(in_.data() + start, i - start)) {
          close_client();
          return;
        }
        start = i + 1;
      }
      if (start == 0 && have == in_.size()) have = 0;  // a line longer than any command: drop
      std::memmove(in_.data(), in_.data() + start, have - start);
      have -= start;
    }
    if (scans_.fetch()) {
      have_scan_ = true;
      const hal::LaserScan& scan = scans_.value();
      if (get_pending_) {
        get_pending_ = false;
        if (!send_scan(get_, scan, -1, scip::kStatusOk)) return close_client();
      }
      if (streaming_) {
        if (skip_ > 0) {
          --skip_;
          continue;
        }
        skip_ = stream_.interval;
        if (stream_.scans > 0) --remaining_;
        if (!send_scan(stream_, scan, stream_.scans > 0 ? remaining_ : -1, scip::kStatusData))
          return close_client();
        if (stream_.scans > 0 && remaining_ == 0) {
          streaming_ = false;
          laser_on_ = false;  // the laser goes off after the last requested scan
        }
      }
    }
  }
}

bool ScipServer::send_scan(const scip::Request& r, const hal::LaserScan& scan, int remaining,
                           const char* status) {
  const int fault = fault_.load();
  if (fault == int(ScipServerFault::Silent) && fault_count_.fetch_sub(1) > 0) return true;
  const scip::Geometry& g = cfg_.geometry;
  const int chars = r.cmd == scip::Command::MS || r.cmd == scip::Command::GS ? 2 : 3;
  const bool me = r.cmd == scip::Command::ME;
  const int cluster = r.cluster > 1 ? r.cluster : 1;
  int n = 0;
  for (int s = r.start_step; s <= r.end_step; s += cluster) {
    // A cluster reports its shortest valid distance, or the first step's code when none is.
    std::uint32_t best = 0;
    bool have_valid = false;
    for (int k = 0; k < cluster && s + k <= r.end_step; ++k) {
      const int beam = s + k - g.amin;
      const std::uint32_t v =
          beam < 0 || beam >= scan.count
              ? scip::kCodeInvalid
              : scip::range_to_wire(scan.ranges_m[std::size_t(beam)], g.dmin_mm, chars);
      const bool valid = v >= std::uint32_t(g.dmin_mm);
      if (k == 0) best = v;
      if (valid && (!have_valid || v < best)) best = v;
      have_valid = have_valid || valid;
    }
    values_[std::size_t(n++)] = best;
    if (me) values_[std::size_t(n++)] = best >= std::uint32_t(g.dmin_mm) ? 1000U : 0U;
  }
  scip::ReplyWriter w(out_.data(), out_.size());
  w.echo(r, remaining);
  w.status(status);
  w.timestamp(now_ms());
  const std::size_t data_at = w.size();
  w.data(values_.data(), n, chars);
  w.end();
  if (!w.ok()) return false;
  std::size_t len = w.size();
  if (fault == int(ScipServerFault::BadChecksum) && fault_count_.fetch_sub(1) > 0) {
    char& sum = out_[std::size_t(std::strchr(out_.data() + data_at, '\n') - out_.data()) - 1];
    sum = sum == '0' ? '1' : '0';
  } else if (fault == int(ScipServerFault::Truncated) && fault_count_.fetch_sub(1) > 0) {
    len = data_at + (len - data_at) / 2;
    out_[len++] = '\n';
    out_[len++] = '\n';
  }
  scans_sent_.fetch_add(1);
  return send_all(out_.data(), len);
}

bool ScipServer::handle_line(const char* line, std::size_t n) {
  commands_.fetch_add(1);
  scip::Request r = scip::parse_request(line, n);
  const scip::Geometry& g = cfg_.geometry;
  const bool data_cmd = r.cmd == scip::Command::MD || r.cmd == scip::Command::MS ||
                        r.cmd == scip::Command::ME || r.cmd == scip::Command::GD ||
                        r.cmd == scip::Command::GS;
  if (data_cmd && r.status[0] == '0' && r.status[1] == '0' && r.end_step > g.amax)
    std::memcpy(r.status, scip::kStatusEndRange, 2);
  const bool ok = r.status[0] == '0' && r.status[1] == '0';
  if (data_cmd && ok && !is_stream(r.cmd) && !laser_on_)
    std::memcpy(r.status, scip::kStatusLaserOff, 2);
  scip::ReplyWriter w(out_.data(), out_.size());
  if (r.cmd == scip::Command::Unknown || !ok || r.status[0] != '0' || r.status[1] != '0') {
    // Errors echo the line as received.
    w.raw_line(line, n);
    w.status(r.status);
    w.end();
    return send_all(out_.data(), w.size());
  }
  char a[32], b[16];
  switch (r.cmd) {
    case scip::Command::VV:
      w.echo(r);
      w.status(scip::kStatusOk);
      w.info("VEND", "Hokuyo Automatic Co., Ltd. (emulated by carril_sim)");
      w.info("PROD", cfg_.model);
      w.info("FIRM", "carril-sim");
      w.info("PROT", "SCIP 2.0");
      w.info("SERI", "H0000000");
      break;
    case scip::Command::PP:
      w.echo(r);
      w.status(scip::kStatusOk);
      w.info("MODL", cfg_.model);
      int_text(g.dmin_mm, a, sizeof a);
      w.info("DMIN", a);
      int_text(g.dmax_mm, a, sizeof a);
      w.info("DMAX", a);
      int_text(g.ares, a, sizeof a);
      w.info("ARES", a);
      int_text(g.amin, a, sizeof a);
      w.info("AMIN", a);
      int_text(g.amax, a, sizeof a);
      w.info("AMAX", a);
      int_text(g.afrt, a, sizeof a);
      w.info("AFRT", a);
      int_text(g.scan_rpm, a, sizeof a);
      w.info("SCAN", a);
      break;
    case scip::Command::II:
      w.echo(r);
      w.status(scip::kStatusOk);
      w.info("MODL", cfg_.model);
      w.info("LASR", laser_on_ ? "ON" : "OFF");
      int_text(g.scan_rpm, b, sizeof b);
      std::snprintf(a, sizeof a, "%s[rpm]", b);
      w.info("SCSP", a);
      w.info("MESM", "Normal");
      w.info("SBPS", "Ethernet 100 [Mbps]");
      std::snprintf(a, sizeof a, "%06X", unsigned(now_ms()));
      w.info("TIME", a);
      w.info("STAT", "Stable 000 no error.");
      break;
    case scip::Command::BM:
      w.echo(r);
      w.status(laser_on_ ? scip::kStatusLaserOn : scip::kStatusOk);
      laser_on_ = true;
      break;
    case scip::Command::QT:
    case scip::Command::RS:
      w.echo(r);
      w.status(scip::kStatusOk);
      streaming_ = false;
      get_pending_ = false;
      laser_on_ = false;
      break;
    case scip::Command::MD:
    case scip::Command::MS:
    case scip::Command::ME:
      w.echo(r);
      w.status(scip::kStatusOk);
      stream_ = r;
      streaming_ = true;
      laser_on_ = true;  // MD switches the laser on by itself
      remaining_ = r.scans;
      skip_ = 0;
      break;
    case scip::Command::GD:
    case scip::Command::GS:
      if (!have_scan_) {
        get_ = r;
        get_pending_ = true;  // answered with the first scan published
        return true;
      }
      return send_scan(r, scans_.value(), -1, scip::kStatusOk);
    case scip::Command::Unknown:
      break;
  }
  w.end();
  return w.ok() && send_all(out_.data(), w.size());
}

}  // namespace carril::sim
