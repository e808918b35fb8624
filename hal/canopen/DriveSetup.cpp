#include "hal/canopen/DriveSetup.hpp"

#include <cmath>
#include <numbers>

#include "hal/canopen/Frames.hpp"

namespace carril::hal::canopen {

namespace {
// A wheel acceleration [rad/s^2] in drive units [counts/s^2], at least 1.
std::uint32_t counts_per_s2(double radps2, const cia402::DriveUnits& u) {
  const double c = radps2 * u.gear_ratio * u.counts_per_rev / (2.0 * std::numbers::pi);
  if (!std::isgreaterequal(c, 1.0)) return 1;  // quiet: a NaN raises no floating-point trap
  if (c >= 4294967295.0) return 4294967295U;
  return static_cast<std::uint32_t>(std::lround(c));
}

class Writer {
 public:
  explicit Writer(SdoWrite* out) : out_(out) {}
  void add(std::uint16_t index, std::uint8_t sub, std::uint32_t value, std::uint8_t size,
           const char* what) {
    if (n_ < kMaxSetupWrites) out_[n_++] = SdoWrite{index, sub, value, size, what};
  }
  // A PDO: disabled (bit 31 of its COB-ID), transmission type 1 (on every SYNC), its mapping
  // replaced by `entries`, then enabled with its COB-ID.
  void pdo(std::uint16_t comm, std::uint16_t map, std::uint32_t cob_id,
           const std::uint32_t* entries, std::uint8_t count, const char* what) {
    add(comm, 1, 0x80000000U | cob_id, 4, what);
    add(comm, 2, 1, 1, what);
    add(map, 0, 0, 1, what);
    for (std::uint8_t i = 0; i < count; ++i) add(map, std::uint8_t(i + 1), entries[i], 4, what);
    add(map, 0, count, 1, what);
    add(comm, 1, cob_id, 4, what);
  }
  std::size_t size() const { return n_; }

 private:
  SdoWrite* out_;
  std::size_t n_ = 0;
};
}  // namespace

std::size_t setup_writes(const DriveSetup& s, SdoWrite* out) {
  Writer w(out);
  w.add(0x6060, 0, static_cast<std::uint8_t>(kProfileVelocityMode), 1,
        "modes of operation: profile velocity");
  w.add(0x6083, 0, counts_per_s2(s.accel_radps2, s.units), 4, "profile acceleration");
  w.add(0x6084, 0, counts_per_s2(s.decel_radps2, s.units), 4, "profile deceleration");
  w.add(0x6085, 0, counts_per_s2(s.quick_stop_decel_radps2, s.units), 4, "quick stop deceleration");
  w.add(0x605A, 0, static_cast<std::uint16_t>(kQuickStopHold), 2, "quick stop option code");
  w.add(0x1016, 1, (std::uint32_t(s.master_node) << 16) | s.master_timeout_ms, 4,
        "consumer heartbeat time (the master's)");
  w.add(0x1017, 0, s.heartbeat_ms, 2, "producer heartbeat time");
  const std::uint32_t rpdo1[] = {0x60400010U, 0x60FF0020U};  // controlword, target velocity
  w.pdo(0x1400, 0x1600, kRpdo1Base + s.node, rpdo1, 2, "RPDO1: controlword, target velocity");
  const std::uint32_t tpdo1[] = {0x60410010U, 0x606C0020U};  // statusword, velocity actual
  w.pdo(0x1800, 0x1A00, kTpdo1Base + s.node, tpdo1, 2, "TPDO1: statusword, velocity actual");
  const std::uint32_t tpdo2[] = {0x60640020U};  // position actual
  w.pdo(0x1801, 0x1A01, kTpdo2Base + s.node, tpdo2, 1, "TPDO2: position actual");
  return w.size();
}

}  // namespace carril::hal::canopen
