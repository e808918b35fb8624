#pragma once
// RangeScanner backend for a Hokuyo laser scanner speaking SCIP 2.0 over TCP (a UST-10LX on port
// 10940, or carril_sim's ScipServer). A reader thread, outside the control tick, connects, sends
// QT and PP to learn the geometry (AMIN, AMAX, ARES, AFRT, DMIN, DMAX, SCAN), starts MD
// streaming of every step from AMIN to AMAX, and publishes each complete, checked scan into a
// lock-free triple buffer. latest() in the tick takes the newest without blocking or copying.
//
// Loss: a connection refused, closed, or silent for data_timeout_ns is closed and retried after
// a backoff that doubles from backoff_min_ns to backoff_max_ns; meanwhile latest() keeps the
// last scan (its seq does not advance), so the firmware's lidar timeout turns the loss into a
// fault. Malformed messages (bad sum, truncated, wrong length) are counted and dropped.
//
// Ranges follow REP 117 (hal/Types.hpp) through hal/scip's wire mapping (wire_to_range);
// stamp_ns is the CLOCK_MONOTONIC time the scan's message was complete (the sensor's own 24-bit
// millisecond stamp is in sensor_stamp_ms()).
#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>

#include "hal/RangeScanner.hpp"
#include "hal/TripleBuffer.hpp"
#include "hal/scip/ScipCodec.hpp"

namespace carril::hal {

struct ScipLidarConfig {
  const char* host = "192.168.0.10";          // sensor address, IPv4 dotted (the UST default)
  std::uint16_t port = 10940;                 // SCIP port of the UST series
  TimeNs connect_timeout_ns = 1'000'000'000;  // [ns]
  TimeNs reply_timeout_ns = 1'000'000'000;    // QT/PP/MD answers [ns]
  TimeNs data_timeout_ns = 500'000'000;       // no scan for this long: reconnect [ns]
  TimeNs backoff_min_ns = 100'000'000;        // first retry delay [ns]
  TimeNs backoff_max_ns = 2'000'000'000;      // retry delay cap [ns]
};

class ScipLidar final : public RangeScanner {
 public:
  ScipLidar();
  ~ScipLidar() override;
  ScipLidar(const ScipLidar&) = delete;
  ScipLidar& operator=(const ScipLidar&) = delete;

  // Starts the reader thread (it connects on its own and keeps retrying). False, with error(),
  // for a host that is not an IPv4 address or bad timeouts; false when already running.
  bool start(const ScipLidarConfig& cfg);
  // Stops and joins the reader thread (returns within about 50 ms); no-op when not running.
  void stop();
  const char* error() const { return error_; }

  // Tick side: the newest complete scan, or nullptr before the first. Never blocks.
  const LaserScan* latest() override;

  // Reader state and counters, readable from any thread.
  bool connected() const { return streaming_.load(); }           // MD acknowledged, scans flowing
  std::uint32_t scans() const { return scans_.load(); }          // scans published
  std::uint32_t malformed() const { return malformed_.load(); }  // messages refused
  std::uint32_t connects() const { return connects_.load(); }    // sessions that reached MD
  std::uint32_t disconnects() const { return disconnects_.load(); }
  std::uint32_t sensor_stamp_ms() const { return sensor_stamp_ms_.load(); }
  // Why the last session ended or failed (static text); "" while none has.
  const char* last_problem() const { return problem_.load(); }
  // The geometry PP reported in the current session (all zero before the first).
  scip::Geometry geometry() const;

 private:
  class Session;
  void run();
  void session(int fd);
  bool sleep_backoff(TimeNs ns);

  ScipLidarConfig cfg_{};
  std::uint32_t addr_ = 0;  // network byte order
  TripleBuffer<LaserScan> buf_;
  bool have_ = false;  // tick side: a scan was taken
  std::thread thread_;
  bool running_ = false;
  std::atomic<bool> stop_{false};
  char error_[128] = {};

  std::atomic<bool> streaming_{false};
  std::atomic<std::uint32_t> scans_{0};
  std::atomic<std::uint32_t> malformed_{0};
  std::atomic<std::uint32_t> connects_{0};
  std::atomic<std::uint32_t> disconnects_{0};
  std::atomic<std::uint32_t> sensor_stamp_ms_{0};
  std::atomic<const char*> problem_{""};
  // Geometry, written by the reader before streaming_ is set; packed for atomic reads.
  std::atomic<int> g_[7] = {};
  std::uint32_t seq_ = 0;
  std::unique_ptr<char[]> rx_;               // received bytes, sized at construction
  std::unique_ptr<std::uint32_t[]> values_;  // one scan's wire values
  std::unique_ptr<scip::Lines> lines_;
};

}  // namespace carril::hal
