#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "hal/WheelDrives.hpp"

namespace carril::hal {
namespace {

TEST(DriveInitResultTest, SuccessNamesNothing) {
  const DriveInitResult r = DriveInitResult::success();
  EXPECT_TRUE(r.ok);
  EXPECT_EQ(r.drive, -1);
  EXPECT_STREQ(r.what, "");
}

TEST(DriveInitResultTest, FailureNamesDriveAndReason) {
  const DriveInitResult r =
      DriveInitResult::failure(2, "drive %d (%s): no boot-up within %.1f s", 2, "rear-left", 1.0);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.drive, 2);
  EXPECT_STREQ(r.what, "drive 2 (rear-left): no boot-up within 1.0 s");
}

TEST(DriveInitResultTest, LongReasonIsCutNotOverrun) {
  const std::string reason(400, 'x');
  const DriveInitResult r = DriveInitResult::failure(-1, "%s", reason.c_str());
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(std::strlen(r.what), std::size_t(DriveInitResult::kMaxText - 1));
}

TEST(DriveInitResultTest, EmptyReasonStillSaysSomething) {
  const DriveInitResult r = DriveInitResult::failure(0, "%s", "");
  EXPECT_FALSE(r.ok);
  EXPECT_STREQ(r.what, "?");
}

}  // namespace
}  // namespace carril::hal
