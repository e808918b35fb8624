#include <gtest/gtest.h>

#include <string>

#include "hal/canopen/SdoAbort.hpp"

namespace carril::hal {
namespace {

TEST(SdoAbortTest, DecodesTheCiA301Table) {
  EXPECT_STREQ(sdo_abort_meaning(0x05030000U), "toggle bit not alternated");
  EXPECT_STREQ(sdo_abort_meaning(0x05040000U), "SDO protocol timed out");
  EXPECT_STREQ(sdo_abort_meaning(0x05040001U), "command specifier not valid or unknown");
  EXPECT_STREQ(sdo_abort_meaning(0x06010000U), "unsupported access to an object");
  EXPECT_STREQ(sdo_abort_meaning(0x06010001U), "attempt to read a write-only object");
  EXPECT_STREQ(sdo_abort_meaning(0x06010002U), "attempt to write a read-only object");
  EXPECT_STREQ(sdo_abort_meaning(0x06020000U), "object does not exist in the object dictionary");
  EXPECT_STREQ(sdo_abort_meaning(0x06040041U), "object cannot be mapped to the PDO");
  EXPECT_STREQ(sdo_abort_meaning(0x06040042U), "mapped objects would exceed the PDO length");
  EXPECT_STREQ(sdo_abort_meaning(0x06040043U), "general parameter incompatibility");
  EXPECT_STREQ(sdo_abort_meaning(0x06060000U), "access failed due to a hardware error");
  EXPECT_STREQ(sdo_abort_meaning(0x06070010U),
               "data type does not match, length of service parameter does not match");
  EXPECT_STREQ(sdo_abort_meaning(0x06070012U),
               "data type does not match, length of service parameter too high");
  EXPECT_STREQ(sdo_abort_meaning(0x06070013U),
               "data type does not match, length of service parameter too low");
  EXPECT_STREQ(sdo_abort_meaning(0x06090011U), "sub-index does not exist");
  EXPECT_STREQ(sdo_abort_meaning(0x06090030U), "value range exceeded");
  EXPECT_STREQ(sdo_abort_meaning(0x06090031U), "value written too high");
  EXPECT_STREQ(sdo_abort_meaning(0x06090032U), "value written too low");
  EXPECT_STREQ(sdo_abort_meaning(0x08000000U), "general error");
  EXPECT_STREQ(sdo_abort_meaning(0x08000020U),
               "data cannot be transferred or stored to the application");
  EXPECT_STREQ(sdo_abort_meaning(0x08000021U),
               "data cannot be transferred or stored because of local control");
  EXPECT_STREQ(sdo_abort_meaning(0x08000022U),
               "data cannot be transferred or stored because of the present device state");
  EXPECT_STREQ(sdo_abort_meaning(0x08000024U), "no data available");
}

TEST(SdoAbortTest, UnknownCodesSaySo) {
  EXPECT_STREQ(sdo_abort_meaning(0U), "unknown abort code");
  EXPECT_STREQ(sdo_abort_meaning(0x06090033U), "unknown abort code");  // next to known ones
  EXPECT_STREQ(sdo_abort_meaning(0xFFFFFFFFU), "unknown abort code");
}

TEST(SdoAbortTest, NamedConstantsMatchTheTable) {
  EXPECT_EQ(std::string(sdo_abort_meaning(kSdoAbortTimeout)), "SDO protocol timed out");
  EXPECT_EQ(std::string(sdo_abort_meaning(kSdoAbortBadCommand)),
            "command specifier not valid or unknown");
  EXPECT_EQ(std::string(sdo_abort_meaning(kSdoAbortValueRange)), "value range exceeded");
}

}  // namespace
}  // namespace carril::hal
