#include "hal/linux/ScipLidar.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>

namespace carril::hal {

namespace {

constexpr std::size_t kRx = 32 * 1024;   // > the longest message (ME, 2048 steps: ~13 kB)
constexpr TimeNs kSliceNs = 50'000'000;  // longest wait before looking at stop_ [ns]

TimeNs monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return TimeNs{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

int poll_ms(TimeNs left) {
  const TimeNs slice = left < kSliceNs ? left : kSliceNs;
  return slice <= 0 ? 0 : int((slice + 999'999) / 1'000'000);
}

enum class Rx : std::uint8_t { Ok, Timeout, Closed, Stopped };

}  // namespace

// One connection's receive side: splits the byte stream into messages (each ends with an empty
// line).
class ScipLidar::Session {
 public:
  Session(ScipLidar& o, int fd) : o_(o), fd_(fd) {}

  bool send(const char* s, std::size_t n) { return ::send(fd_, s, n, MSG_NOSIGNAL) == ssize_t(n); }

  // Waits until timeout_ns for the next message: then it is at rx_[0..len).
  Rx next(TimeNs timeout_ns, std::size_t& len) {
    drop();
    const TimeNs deadline = monotonic_ns() + timeout_ns;
    for (;;) {
      // A stray empty line between messages is skipped, not taken for an end.
      std::size_t skip = 0;
      while (skip < have_ && o_.rx_[skip] == '\n') ++skip;
      if (skip > 0) consume(skip);
      for (std::size_t i = 0; i + 1 < have_; ++i) {
        if (o_.rx_[i] == '\n' && o_.rx_[i + 1] == '\n') {
          len = used_ = i + 2;
          return Rx::Ok;
        }
      }
      if (have_ == kRx) {  // no end in a full buffer: garbage; start again
        o_.malformed_.fetch_add(1);
        have_ = 0;
      }
      if (o_.stop_.load()) return Rx::Stopped;
      const TimeNs left = deadline - monotonic_ns();
      if (left <= 0) return Rx::Timeout;
      pollfd p{fd_, POLLIN, 0};
      const int r = poll(&p, 1, poll_ms(left));
      if (r < 0 && errno != EINTR) return Rx::Closed;
      if (r <= 0) continue;
      const ssize_t k = recv(fd_, o_.rx_.get() + have_, kRx - have_, 0);
      if (k == 0 || (k < 0 && errno != EAGAIN && errno != EINTR)) return Rx::Closed;
      if (k > 0) have_ += std::size_t(k);
    }
  }

  // Waits for the reply to the command `c0 c1` (any earlier message, e.g. a scan still in
  // flight after QT, is skipped).
  Rx reply(char c0, char c1, TimeNs timeout_ns, std::size_t& len) {
    const TimeNs deadline = monotonic_ns() + timeout_ns;
    for (;;) {
      const Rx r = next(deadline - monotonic_ns(), len);
      if (r != Rx::Ok) return r;
      if (len >= 2 && o_.rx_[0] == c0 && o_.rx_[1] == c1) return r;
    }
  }

 private:
  void drop() {
    consume(used_);
    used_ = 0;
  }
  void consume(std::size_t n) {
    std::memmove(o_.rx_.get(), o_.rx_.get() + n, have_ - n);
    have_ -= n;
  }
  ScipLidar& o_;
  int fd_;
  std::size_t have_ = 0;
  std::size_t used_ = 0;  // length of the message handed out last
};

ScipLidar::ScipLidar()
    : rx_(std::make_unique<char[]>(kRx)),
      values_(std::make_unique<std::uint32_t[]>(std::size_t(kMaxScanBeams))),
      lines_(std::make_unique<scip::Lines>()) {}

ScipLidar::~ScipLidar() {
  stop();
}

bool ScipLidar::start(const ScipLidarConfig& cfg) {
  if (running_) return false;
  in_addr a{};
  if (cfg.host == nullptr || inet_pton(AF_INET, cfg.host, &a) != 1) {
    std::snprintf(error_, sizeof error_, "lidar: host '%s' is not an IPv4 address",
                  cfg.host != nullptr ? cfg.host : "(null)");
    return false;
  }
  if (cfg.connect_timeout_ns <= 0 || cfg.reply_timeout_ns <= 0 || cfg.data_timeout_ns <= 0 ||
      cfg.backoff_min_ns <= 0 || cfg.backoff_max_ns < cfg.backoff_min_ns) {
    std::snprintf(error_, sizeof error_,
                  "lidar: timeouts must be > 0 and backoff_max_ns >= backoff_min_ns");
    return false;
  }
  cfg_ = cfg;
  addr_ = a.s_addr;
  error_[0] = '\0';
  stop_ = false;
  thread_ = std::thread([this] { run(); });
  running_ = true;
  return true;
}

void ScipLidar::stop() {
  if (!running_) return;
  stop_ = true;
  thread_.join();
  running_ = false;
}

const LaserScan* ScipLidar::latest() {
  if (buf_.fetch()) have_ = true;
  return have_ ? &buf_.value() : nullptr;
}

scip::Geometry ScipLidar::geometry() const {
  scip::Geometry g;
  g.dmin_mm = g_[0].load();
  g.dmax_mm = g_[1].load();
  g.ares = g_[2].load();
  g.amin = g_[3].load();
  g.amax = g_[4].load();
  g.afrt = g_[5].load();
  g.scan_rpm = g_[6].load();
  return g;
}

bool ScipLidar::sleep_backoff(TimeNs ns) {
  const TimeNs until = monotonic_ns() + ns;
  while (!stop_.load()) {
    const TimeNs left = until - monotonic_ns();
    if (left <= 0) return true;
    const TimeNs slice = left < kSliceNs ? left : kSliceNs;
    timespec ts{0, long(slice)};
    nanosleep(&ts, nullptr);
  }
  return false;
}

void ScipLidar::run() {
  TimeNs backoff = cfg_.backoff_min_ns;
  while (!stop_.load()) {
    const int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    sockaddr_in sa{};
    sa.sin_family = AF_INET;
    sa.sin_port = htons(cfg_.port);
    sa.sin_addr.s_addr = addr_;
    bool up = false;
    if (fd >= 0) {
      const int one = 1;
      setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
      int r = connect(fd, reinterpret_cast<sockaddr*>(&sa), sizeof sa);
      if (r != 0 && errno == EINPROGRESS) {
        const TimeNs deadline = monotonic_ns() + cfg_.connect_timeout_ns;
        while (!stop_.load() && monotonic_ns() < deadline) {
          pollfd p{fd, POLLOUT, 0};
          if (poll(&p, 1, poll_ms(deadline - monotonic_ns())) > 0) {
            int err = 0;
            socklen_t len = sizeof err;
            getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len);
            r = err == 0 ? 0 : -1;
            break;
          }
        }
      }
      up = r == 0;
    }
    if (up) {
      session(fd);
    } else {
      problem_ = "connection refused or timed out";
    }
    if (fd >= 0) close(fd);
    if (streaming_.load()) {
      // The session had streamed: retry quickly, then slower again.
      streaming_ = false;
      disconnects_.fetch_add(1);
      backoff = cfg_.backoff_min_ns;
    }
    if (!sleep_backoff(backoff)) break;
    backoff = backoff * 2 < cfg_.backoff_max_ns ? backoff * 2 : cfg_.backoff_max_ns;
  }
  streaming_ = false;
}

void ScipLidar::session(int fd) {
  Session s(*this, fd);
  char cmd[32];
  std::size_t len = 0;
  // QT first: a sensor left streaming by an earlier client stops, so PP's reply is not mixed
  // with scans.
  std::size_t n = scip::format_simple_request(scip::Command::QT, cmd, sizeof cmd);
  if (!s.send(cmd, n) || s.reply('Q', 'T', cfg_.reply_timeout_ns, len) != Rx::Ok)
    return void(problem_ = "no answer to QT");
  n = scip::format_simple_request(scip::Command::PP, cmd, sizeof cmd);
  if (!s.send(cmd, n) || s.reply('P', 'P', cfg_.reply_timeout_ns, len) != Rx::Ok)
    return void(problem_ = "no answer to PP");
  scip::Geometry g;
  const char* why = "";
  if (!scip::split_lines(rx_.get(), len, *lines_) || !scip::parse_pp(*lines_, g, why) ||
      g.amax - g.amin + 1 > kMaxScanBeams) {
    malformed_.fetch_add(1);
    return void(problem_ = "PP reply malformed, incomplete or more steps than kMaxScanBeams");
  }
  const int values[7] = {g.dmin_mm, g.dmax_mm, g.ares, g.amin, g.amax, g.afrt, g.scan_rpm};
  for (int i = 0; i < 7; ++i) g_[i] = values[i];

  n = scip::format_data_request(scip::Command::MD, g.amin, g.amax, 1, 0, 0, cmd, sizeof cmd);
  if (!s.send(cmd, n) || s.reply('M', 'D', cfg_.reply_timeout_ns, len) != Rx::Ok)
    return void(problem_ = "no answer to MD");
  scip::Distances d;
  if (!scip::split_lines(rx_.get(), len, *lines_) ||
      scip::parse_distances(*lines_, values_.get(), nullptr, kMaxScanBeams, d) !=
          scip::ReplyError::None ||
      d.has_data)
    return void(problem_ = "MD refused (error status) or its acknowledgement malformed");
  streaming_ = true;
  connects_.fetch_add(1);

  const double step = 2.0 * M_PI / g.ares;
  while (!stop_.load()) {
    const Rx r = s.next(cfg_.data_timeout_ns, len);
    if (r == Rx::Stopped) return;
    if (r == Rx::Timeout) return void(problem_ = "no scan within data_timeout_ns");
    if (r == Rx::Closed) return void(problem_ = "connection closed");
    if (!scip::split_lines(rx_.get(), len, *lines_) ||
        scip::parse_distances(*lines_, values_.get(), nullptr, kMaxScanBeams, d) !=
            scip::ReplyError::None ||
        !d.has_data || d.echo.cmd != scip::Command::MD || d.echo.start_step != g.amin ||
        d.echo.end_step != g.amax) {
      malformed_.fetch_add(1);
      continue;
    }
    LaserScan& out = buf_.write_slot();
    out.seq = ++seq_;
    out.stamp_ns = monotonic_ns();
    out.angle_min_rad = float((d.echo.start_step - g.afrt) * step);
    out.angle_increment_rad = float(step);
    out.range_min_m = float(g.dmin_mm / 1000.0);
    out.range_max_m = float(g.dmax_mm / 1000.0);
    out.count = std::uint16_t(d.count);
    for (int i = 0; i < d.count; ++i)
      out.ranges_m[std::size_t(i)] = scip::wire_to_range(values_[std::size_t(i)], g.dmin_mm);
    buf_.publish();
    sensor_stamp_ms_ = d.stamp_ms;
    scans_.fetch_add(1);
  }
}

}  // namespace carril::hal
