#pragma once
// The simulator's 2D lidar served as a Hokuyo SCIP 2.0 device over TCP, as a UST-10LX serves
// its scans on port 10940: VV, PP, II, BM, QT, RS, MD/MS/ME (streaming), GD/GS (one scan), with
// the status codes, sums and time stamps of the protocol; an unknown command gets status 0E.
// One client at a time (as the sensor); further clients wait in the listen backlog.
//
// The simulator's side never blocks: publish(scan) writes into a lock-free triple buffer and a
// server thread encodes and sends. Faults can be injected to test clients.
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

#include "hal/TripleBuffer.hpp"
#include "hal/Types.hpp"
#include "hal/scip/ScipCodec.hpp"

namespace carril::sim {

struct ScipServerConfig {
  const char* bind_address = "127.0.0.1";  // IPv4, dotted
  std::uint16_t port = 10940;              // 0: an ephemeral port (see ScipServer::port())
  hal::scip::Geometry geometry;            // what PP reports; ScipServer::geometry_for() builds it
  const char* model = "UST-10LX";          // PROD (VV) and MODL (PP, II)
};

// Faults a served lidar can be given, each for the next `count` scans (Disconnect: once).
enum class ScipServerFault : std::uint8_t {
  None,
  BadChecksum,  // one data line's sum is wrong
  Truncated,    // the scan is cut in the middle of its data and ended early
  Silent,       // scans are not sent (the connection stays open)
  Disconnect,   // the server closes the client's connection
};

class ScipServer {
 public:
  ScipServer();
  ~ScipServer();
  ScipServer(const ScipServer&) = delete;
  ScipServer& operator=(const ScipServer&) = delete;

  // The SCIP geometry of scans shaped like `shape` (angle_min_rad, angle_increment_rad, count,
  // range_min_m, range_max_m); scan_rpm: the scan rate [rpm] (60 x rate in Hz). False, with the
  // reason in why (static text), when the beams are not whole steps of a full turn.
  static bool geometry_for(const hal::LaserScan& shape, int scan_rpm, hal::scip::Geometry& g,
                           const char*& why);

  // Binds, listens and starts the server thread. False, with error(), for a bad config or when
  // the port cannot be bound; false when already running.
  bool start(const ScipServerConfig& cfg);
  // Closes the connection and joins the thread; no-op when not running.
  void stop();
  bool running() const { return running_; }
  // The port listened on (the ephemeral one when config port was 0).
  std::uint16_t port() const { return port_; }
  const char* error() const { return error_; }

  // Simulator side, each lidar period: the newest scan (copied once; never blocks). A scan
  // whose count is not AMAX - AMIN + 1 is counted (shape_mismatches()) and not served.
  void publish(const hal::LaserScan& scan);
  // Test side: the next `count` scans get fault f (any thread).
  void inject(ScipServerFault f, int count = 1);

  // Counters, readable from any thread.
  std::uint32_t clients() const { return clients_.load(); }        // connections accepted
  std::uint32_t scans_sent() const { return scans_sent_.load(); }  // scan messages sent
  std::uint32_t commands() const { return commands_.load(); }      // command lines handled
  std::uint32_t shape_mismatches() const { return shape_mismatches_.load(); }

 private:
  void loop();
  void serve_client();
  bool handle_line(const char* line, std::size_t n);
  bool send_scan(const hal::scip::Request& r, const hal::LaserScan& scan, int remaining,
                 const char* status);
  bool send_all(const char* data, std::size_t n);
  void close_client();
  // Wakes the server thread's poll() (any thread).
  void wake();
  std::uint32_t now_ms() const;

  ScipServerConfig cfg_{};
  hal::TripleBuffer<hal::LaserScan> scans_;
  int listen_fd_ = -1;
  int client_fd_ = -1;
  int wake_fd_ = -1;  // an eventfd: publish(), inject() and stop() wake the server thread
  std::uint16_t port_ = 0;
  bool running_ = false;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  char error_[160] = {};

  // Server thread's state.
  std::vector<char> in_;   // received command bytes
  std::vector<char> out_;  // one reply
  std::vector<std::uint32_t> values_;
  bool laser_on_ = false;
  bool streaming_ = false;
  bool get_pending_ = false;  // GD/GS waiting for the first scan
  hal::scip::Request stream_{};
  hal::scip::Request get_{};
  int remaining_ = 0;       // MD scans still to send (scans > 0 only)
  int skip_ = 0;            // scans to skip before the next one sent (interval)
  bool have_scan_ = false;  // front() holds a published scan
  std::int64_t start_ns_ = 0;

  std::atomic<int> fault_{0};
  std::atomic<int> fault_count_{0};
  std::atomic<std::uint32_t> clients_{0};
  std::atomic<std::uint32_t> scans_sent_{0};
  std::atomic<std::uint32_t> commands_{0};
  std::atomic<std::uint32_t> shape_mismatches_{0};
};

}  // namespace carril::sim
