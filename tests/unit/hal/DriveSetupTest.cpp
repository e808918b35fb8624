// DriveSetup: the SDO writes of a drive's bring-up, in order and with their exact values.
#include "hal/canopen/DriveSetup.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <string>

namespace carril::hal::canopen {
namespace {

struct Want {
  std::uint16_t index;
  std::uint8_t sub;
  std::uint32_t value;
  std::uint8_t size;
};

TEST(DriveSetupTest, WritesProfileVelocityRampsHeartbeatsAndPdosInOrder) {
  DriveSetup s;
  s.node = 3;
  s.units = {4096.0, 10.0};
  s.accel_radps2 = 2.0 * std::numbers::pi;  // one wheel rev/s^2 = 40,960 counts/s^2
  s.decel_radps2 = 4.0 * std::numbers::pi;
  s.quick_stop_decel_radps2 = 8.0 * std::numbers::pi;
  s.heartbeat_ms = 50;
  s.master_node = 127;
  s.master_timeout_ms = 150;
  SdoWrite w[kMaxSetupWrites];
  const std::size_t n = setup_writes(s, w);
  const Want want[] = {
      {0x6060, 0, 3, 1},
      {0x6083, 0, 40960, 4},
      {0x6084, 0, 81920, 4},
      {0x6085, 0, 163840, 4},
      {0x605A, 0, 6, 2},
      {0x1016, 1, (127U << 16) | 150U, 4},
      {0x1017, 0, 50, 2},
      // RPDO1: disable, on SYNC, mapping controlword + target velocity, enable
      {0x1400, 1, 0x80000203U, 4},
      {0x1400, 2, 1, 1},
      {0x1600, 0, 0, 1},
      {0x1600, 1, 0x60400010U, 4},
      {0x1600, 2, 0x60FF0020U, 4},
      {0x1600, 0, 2, 1},
      {0x1400, 1, 0x203, 4},
      // TPDO1: statusword + velocity actual
      {0x1800, 1, 0x80000183U, 4},
      {0x1800, 2, 1, 1},
      {0x1A00, 0, 0, 1},
      {0x1A00, 1, 0x60410010U, 4},
      {0x1A00, 2, 0x606C0020U, 4},
      {0x1A00, 0, 2, 1},
      {0x1800, 1, 0x183, 4},
      // TPDO2: position actual
      {0x1801, 1, 0x80000283U, 4},
      {0x1801, 2, 1, 1},
      {0x1A01, 0, 0, 1},
      {0x1A01, 1, 0x60640020U, 4},
      {0x1A01, 0, 1, 1},
      {0x1801, 1, 0x283, 4},
  };
  ASSERT_EQ(n, std::size(want));
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(w[i].index, want[i].index) << i;
    EXPECT_EQ(w[i].subindex, want[i].sub) << i;
    EXPECT_EQ(w[i].value, want[i].value) << i << " " << w[i].what;
    EXPECT_EQ(w[i].size, want[i].size) << i;
    EXPECT_STRNE(w[i].what, "") << i;
  }
  EXPECT_EQ(std::string(w[9].what), "RPDO1: controlword, target velocity");
}

TEST(DriveSetupTest, RampsNeverZeroOrWrapped) {
  DriveSetup s;
  s.accel_radps2 = 0.0;                                       // would let the drive never move
  s.decel_radps2 = std::numeric_limits<double>::quiet_NaN();  // a bad number
  s.quick_stop_decel_radps2 = 1e12;
  SdoWrite w[kMaxSetupWrites];
  setup_writes(s, w);
  EXPECT_EQ(w[1].value, 1U);
  EXPECT_EQ(w[2].value, 1U);
  EXPECT_EQ(w[3].value, 4294967295U);
}

}  // namespace
}  // namespace carril::hal::canopen
