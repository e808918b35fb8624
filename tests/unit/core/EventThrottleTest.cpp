// EventThrottle: faults always pass; other events at most N per window, the rest counted.
#include "firmware/core/EventThrottle.hpp"

#include <gtest/gtest.h>

namespace carril::fw {
namespace {

constexpr hal::TimeNs kS = 1'000'000'000;

Event at(hal::TimeNs t, EventKind k = EventKind::StateChange) {
  Event e;
  e.t_ns = t;
  e.kind = k;
  if (k == EventKind::Fault) e.severity = Severity::Error;
  return e;
}

TEST(EventThrottleTest, PassesNPerWindowCountsTheRestAndAlwaysPassesFaults) {
  EventLog<256> log;
  EventThrottle th(log, 4, kS);
  for (int i = 0; i < 10; ++i) th.push(at(i * kS / 100));  // 10 in the first 0.1 s
  EXPECT_EQ(log.size(), 4U);
  EXPECT_EQ(th.throttled(), 6U);
  th.push(at(kS / 2, EventKind::Fault));  // over the budget, yet logged
  EXPECT_EQ(log.size(), 5U);
  for (int i = 0; i < 10; ++i) th.push(at(kS + i));  // a new window: 4 more
  EXPECT_EQ(log.size(), 9U);
  EXPECT_EQ(th.throttled(), 12U);
  EXPECT_EQ(log.dropped(), 0U);
}

}  // namespace
}  // namespace carril::fw
