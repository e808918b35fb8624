// CANopen frames: exact bytes of what the master sends (NMT, SYNC, heartbeat, RPDO1), decoding of
// what drives send (heartbeat, EMCY, TPDO1, TPDO2), and frames of another node, kind or length
// refused rather than misread.
#include "hal/canopen/Frames.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace carril::hal::canopen {
namespace {

std::vector<int> bytes(const CanFrame& f) {
  return std::vector<int>(f.data, f.data + f.len);
}

TEST(CanopenFrames, MasterFramesHaveTheirExactBytes) {
  const CanFrame start = nmt(NmtCommand::Start, 3);
  EXPECT_EQ(start.id, 0x000U);
  EXPECT_EQ(bytes(start), (std::vector<int>{0x01, 3}));
  EXPECT_EQ(bytes(nmt(NmtCommand::ResetCommunication, 0)), (std::vector<int>{0x82, 0}));
  EXPECT_EQ(bytes(nmt(NmtCommand::EnterPreOperational, 5)), (std::vector<int>{0x80, 5}));
  const CanFrame s = sync_frame();
  EXPECT_EQ(s.id, 0x080U);
  EXPECT_EQ(s.len, 0);
  const CanFrame hb = heartbeat(1, NmtState::Operational);
  EXPECT_EQ(hb.id, 0x701U);
  EXPECT_EQ(bytes(hb), (std::vector<int>{0x05}));
  // Controlword 0x000F, target velocity -2 counts/s, little-endian.
  const CanFrame r = rpdo1(4, 0x000F, -2);
  EXPECT_EQ(r.id, 0x204U);
  EXPECT_EQ(bytes(r), (std::vector<int>{0x0F, 0x00, 0xFE, 0xFF, 0xFF, 0xFF}));
}

TEST(CanopenFrames, DecodesWhatDrivesSend) {
  std::uint8_t node = 0, state = 0;
  ASSERT_TRUE(decode_heartbeat(heartbeat(9, NmtState::PreOperational), node, state));
  EXPECT_EQ(node, 9);
  EXPECT_EQ(state, 0x7F);
  EXPECT_STREQ(nmt_state_name(state), "pre-operational");

  CanFrame t1;
  t1.id = 0x182;
  t1.len = 6;
  const std::uint8_t d1[] = {0x27, 0x06, 0x00, 0x40, 0x01, 0x00};  // 0x0627, 0x00014000
  std::copy(d1, d1 + 6, t1.data);
  std::uint16_t sw = 0;
  std::int32_t v = 0;
  ASSERT_TRUE(decode_tpdo1(t1, 2, sw, v));
  EXPECT_EQ(sw, 0x0627);
  EXPECT_EQ(v, 0x14000);

  CanFrame t2;
  t2.id = 0x282;
  t2.len = 4;
  const std::uint8_t d2[] = {0x00, 0x00, 0x00, 0x80};  // INT32_MIN
  std::copy(d2, d2 + 4, t2.data);
  std::int32_t p = 0;
  ASSERT_TRUE(decode_tpdo2(t2, 2, p));
  EXPECT_EQ(p, -2147483647 - 1);

  CanFrame e;
  e.id = 0x083;
  e.len = 8;
  const std::uint8_t de[] = {0x10, 0x23, 0x02, 1, 2, 3, 4, 5};
  std::copy(de, de + 8, e.data);
  Emcy em;
  ASSERT_TRUE(decode_emcy(e, em));
  EXPECT_EQ(em.node, 3);
  EXPECT_EQ(em.error_code, 0x2310);
  EXPECT_EQ(em.error_register, 0x02);
  EXPECT_EQ(em.vendor[4], 5);
  EXPECT_STREQ(emcy_meaning(em.error_code), "continuous over-current");
  EXPECT_STREQ(emcy_meaning(0x3199), "voltage");
  EXPECT_STREQ(emcy_meaning(0xFF01), "additional functions or device specific");
}

TEST(CanopenFrames, RefusesOtherNodesKindsAndLengths) {
  std::uint16_t sw = 0;
  std::int32_t v = 0, p = 0;
  CanFrame t1 = rpdo1(2, 0x27, 5);  // right length, wrong function (an RPDO)
  EXPECT_FALSE(decode_tpdo1(t1, 2, sw, v));
  t1.id = 0x183;  // another node's TPDO1
  EXPECT_FALSE(decode_tpdo1(t1, 2, sw, v));
  t1.id = 0x182;
  t1.len = 5;  // truncated
  EXPECT_FALSE(decode_tpdo1(t1, 2, sw, v));
  t1.len = 6;
  t1.rtr = true;
  EXPECT_FALSE(decode_tpdo1(t1, 2, sw, v));
  t1.rtr = false;
  t1.extended = true;
  EXPECT_FALSE(decode_tpdo1(t1, 2, sw, v));
  t1.extended = false;
  EXPECT_TRUE(decode_tpdo1(t1, 2, sw, v));
  CanFrame t2;
  t2.id = 0x282;
  t2.len = 8;
  EXPECT_FALSE(decode_tpdo2(t2, 2, p));
  Emcy em;
  EXPECT_FALSE(decode_emcy(sync_frame(), em));  // SYNC shares the function code, node 0
  CanFrame short_emcy;
  short_emcy.id = 0x081;
  short_emcy.len = 7;
  EXPECT_FALSE(decode_emcy(short_emcy, em));
  std::uint8_t node = 0, state = 0;
  CanFrame hb = heartbeat(1, NmtState::Stopped);
  hb.len = 2;
  EXPECT_FALSE(decode_heartbeat(hb, node, state));
  hb = heartbeat(1, NmtState::Stopped);
  hb.id = 0x700;  // node 0 does not exist
  EXPECT_FALSE(decode_heartbeat(hb, node, state));
  hb.error = true;
  hb.id = 0x701;
  EXPECT_FALSE(decode_heartbeat(hb, node, state));
}

}  // namespace
}  // namespace carril::hal::canopen
