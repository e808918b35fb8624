// CARRIL_CHECK: always on (the Release build keeps it), counts every failure, keeps the first
// one's place, and the containers built on it refuse what would reach outside their storage.
#include "firmware/core/Check.hpp"

#include <gtest/gtest.h>

#include <cstring>

#include "firmware/core/RingBuffer.hpp"
#include "firmware/core/StaticVector.hpp"

namespace carril::fw {
namespace {

TEST(CheckTest, APassingCheckIsTrueAndCountsNothing) {
  const std::uint32_t before = check_failures().count;
  EXPECT_TRUE(CARRIL_CHECK(1 + 1 == 2));
  EXPECT_EQ(check_failures().count, before);
}

TEST(CheckTest, AFailedCheckIsFalseCountedAndKeepsTheFirstPlace) {
  const std::uint32_t before = check_failures().count;
  const int line = __LINE__ + 1;
  EXPECT_FALSE(CARRIL_CHECK(1 + 1 == 3));
  EXPECT_FALSE(CARRIL_CHECK(false));
  const CheckFailures f = check_failures();
  EXPECT_EQ(f.count, before + 2);
  ASSERT_NE(f.file, nullptr);
  if (before == 0) {  // the first failure of this process is this test's
    EXPECT_NE(std::strstr(f.file, "CheckTest.cpp"), nullptr) << f.file;
    EXPECT_EQ(f.line, line);
  }
}

TEST(CheckTest, StaticVectorRefusesAPushWhenFullAndClampsABadIndex) {
  const std::uint32_t before = check_failures().count;
  StaticVector<int, 2> v;
  EXPECT_TRUE(v.push_back(1));
  EXPECT_TRUE(v.push_back(2));
  EXPECT_FALSE(v.push_back(3));
  EXPECT_EQ(v.size(), 2U);
  EXPECT_EQ(check_failures().count, before + 1);
  EXPECT_EQ(v[5], 2);  // clamped to the storage's last element
  EXPECT_EQ(check_failures().count, before + 2);
  v.clear();
  v.pop_back();  // empty: refused
  EXPECT_EQ(v.size(), 0U);
  EXPECT_EQ(check_failures().count, before + 3);
  EXPECT_TRUE(v.try_push_back(7));  // the handled form counts nothing
  EXPECT_EQ(check_failures().count, before + 3);
}

TEST(CheckTest, RingBufferCountsAnIndexPastItsSize) {
  const std::uint32_t before = check_failures().count;
  RingBuffer<int, 4> b;
  b.push(1);
  EXPECT_EQ(b[0], 1);
  EXPECT_EQ(check_failures().count, before);
  (void)b[3];
  EXPECT_EQ(check_failures().count, before + 1);
}

}  // namespace
}  // namespace carril::fw
