#include "firmware/core/StaticVector.hpp"

#include <gtest/gtest.h>

namespace carril::fw {
namespace {

// capacity() is usable in constant expressions.
static_assert(StaticVector<int, 4>{}.capacity() == 4);
static_assert(StaticVector<double, 1>{}.capacity() == 1);
// The whole container works at compile time.
static_assert([] {
  StaticVector<int, 3> v;
  v.push_back(1);
  v.push_back(2);
  return v.size() == 2 && v[1] == 2 && !v.full();
}());

TEST(StaticVectorTest, StartsEmpty) {
  StaticVector<int, 4> v;
  EXPECT_TRUE(v.empty());
  EXPECT_FALSE(v.full());
  EXPECT_EQ(v.size(), 0U);
  EXPECT_EQ(v.capacity(), 4U);
  EXPECT_EQ(v.begin(), v.end());
}

TEST(StaticVectorTest, PushToCapacity) {
  StaticVector<int, 4> v;
  for (int i = 0; i < 4; ++i) {
    EXPECT_FALSE(v.full());
    EXPECT_TRUE(v.push_back(10 * i));
    EXPECT_EQ(v.size(), static_cast<std::size_t>(i + 1));
  }
  EXPECT_TRUE(v.full());
  EXPECT_FALSE(v.empty());
  EXPECT_EQ(v[0], 0);
  EXPECT_EQ(v[1], 10);
  EXPECT_EQ(v[2], 20);
  EXPECT_EQ(v[3], 30);
  EXPECT_EQ(v.back(), 30);
}

TEST(StaticVectorTest, PushOnFullIsRefused) {
  StaticVector<int, 2> v;
  ASSERT_TRUE(v.push_back(1));
  ASSERT_TRUE(v.push_back(2));
#ifdef NDEBUG
  // Release: the push is refused and the contents are untouched.
  EXPECT_FALSE(v.push_back(3));
  EXPECT_EQ(v.size(), 2U);
  EXPECT_EQ(v[0], 1);
  EXPECT_EQ(v[1], 2);
#else
  // Debug: pushing on a full vector is a programming error caught by the assert.
  EXPECT_DEATH(v.push_back(3), "StaticVector full");
#endif
}

// A full vector met as an input condition (a path longer than its output): refused without the
// assert, in every build type.
TEST(StaticVectorTest, TryPushOnFullIsRefusedInEveryBuild) {
  StaticVector<int, 2> v;
  EXPECT_TRUE(v.try_push_back(1));
  EXPECT_TRUE(v.try_push_back(2));
  EXPECT_FALSE(v.try_push_back(3));
  EXPECT_EQ(v.size(), 2U);
  EXPECT_EQ(v[0], 1);
  EXPECT_EQ(v[1], 2);
}

TEST(StaticVectorTest, ClearEmptiesAndAllowsReuse) {
  StaticVector<int, 3> v;
  v.push_back(7);
  v.push_back(8);
  v.push_back(9);
  v.clear();
  EXPECT_TRUE(v.empty());
  EXPECT_EQ(v.size(), 0U);
  EXPECT_EQ(v.begin(), v.end());
  EXPECT_TRUE(v.push_back(42));
  EXPECT_EQ(v.size(), 1U);
  EXPECT_EQ(v[0], 42);
}

TEST(StaticVectorTest, PopBackRemovesLast) {
  StaticVector<int, 3> v;
  v.push_back(1);
  v.push_back(2);
  v.pop_back();
  EXPECT_EQ(v.size(), 1U);
  EXPECT_EQ(v.back(), 1);
}

TEST(StaticVectorTest, IterationVisitsElementsInOrder) {
  StaticVector<int, 8> v;
  for (int x : {3, 1, 4, 1, 5}) v.push_back(x);
  int seen[5] = {};
  int n = 0;
  for (int x : v) seen[n++] = x;
  ASSERT_EQ(n, 5);
  EXPECT_EQ(seen[0], 3);
  EXPECT_EQ(seen[1], 1);
  EXPECT_EQ(seen[2], 4);
  EXPECT_EQ(seen[3], 1);
  EXPECT_EQ(seen[4], 5);
  EXPECT_EQ(v.end() - v.begin(), 5);

  // Mutable iteration writes through.
  for (int& x : v) x *= 2;
  const StaticVector<int, 8>& cv = v;
  int sum = 0;
  for (int x : cv) sum += x;
  EXPECT_EQ(sum, 2 * (3 + 1 + 4 + 1 + 5));
}

}  // namespace
}  // namespace carril::fw
