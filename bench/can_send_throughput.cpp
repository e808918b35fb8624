// carril_can_throughput: sends N classic CAN frames (8 data bytes, ids cycling 0x100..0x4FF) as
// fast as possible through SocketCanBus and prints the rate, to compare with can-utils'
// `cangen IFACE -g 0 -n N` on the same interface (tools/uml/bench_vcan.sh runs both inside
// user-mode-linux on vcan0).
// Usage: carril_can_throughput [--iface vcan0] [-n 200000]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

#include "hal/linux/SocketCanBus.hpp"

namespace {

double now_s() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return double(ts.tv_sec) + double(ts.tv_nsec) * 1e-9;
}

}  // namespace

int main(int argc, char** argv) {
  using carril::hal::CanFrame;
  using carril::hal::SocketCanBus;
  SocketCanBus::Config cfg;
  cfg.iface = "vcan0";
  cfg.tx_backlog = 64;
  cfg.send_deadline_ns = 1'000'000'000;  // a throughput run: hold frames rather than drop them
  long n = 200'000;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--iface") == 0 && i + 1 < argc) {
      cfg.iface = argv[++i];
    } else if (std::strcmp(argv[i], "-n") == 0 && i + 1 < argc) {
      n = std::strtol(argv[++i], nullptr, 10);
    } else if (std::strcmp(argv[i], "--batch") == 0 && i + 1 < argc) {
      cfg.tx_batch = static_cast<int>(std::strtol(argv[++i], nullptr, 10));
    } else {
      std::fprintf(stderr, "usage: %s [--iface vcan0] [-n FRAMES] [--batch N]\n", argv[0]);
      return 2;
    }
  }
  if (n <= 0) {
    std::fprintf(stderr, "carril_can_throughput: -n wants a positive frame count\n");
    return 2;
  }
  SocketCanBus::OpenResult r = SocketCanBus::open(cfg);
  if (!r.bus) {
    std::fprintf(stderr, "carril_can_throughput: %s\n", r.error.c_str());
    return 1;
  }
  SocketCanBus& bus = *r.bus;
  CanFrame f;
  f.len = 8;
  long refused = 0;
  const double t0 = now_s();
  for (long i = 0; i < n; ++i) {
    f.id = 0x100U + std::uint32_t(i & 0x3FF);
    std::memcpy(f.data, &i, sizeof i);
    while (!bus.send(f)) {  // the backlog is full: let the kernel catch up
      ++refused;
      if (bus.link_down()) {
        std::fprintf(stderr, "carril_can_throughput: %s went down\n", cfg.iface.c_str());
        return 1;
      }
    }
  }
  bus.flush();  // the last batch
  CanFrame sink;
  while (bus.backlog() > 0) bus.receive(sink);  // flushes what the kernel had no room for
  const double dt = now_s() - t0;
  const auto c = bus.counters();
  std::printf(
      "carril SocketCanBus on %s: %ld frames in %.3f s = %.0f frames/s (tx_frames %llu, "
      "tx_dropped %llu, sends refused for a full backlog %ld)\n",
      cfg.iface.c_str(), n, dt, double(n) / dt, static_cast<unsigned long long>(c.tx_frames),
      static_cast<unsigned long long>(c.tx_dropped), refused);
  return c.tx_frames == std::uint64_t(n) ? 0 : 1;
}
