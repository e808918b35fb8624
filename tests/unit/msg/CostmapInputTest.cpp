// CostmapInput: every consumer's one way to the costmap view; a missing view where one is
// required is a counted programming error with the empty view (never built) as the way out.
#include "firmware/msg/CostmapView.hpp"

#include <gtest/gtest.h>

#include "firmware/core/Check.hpp"

namespace carril::fw {
namespace {

class OneGridView final : public CostmapView {
 public:
  OneGridView() { grid_.init(4, 3, 0.1, 0); }
  const RollingGrid<std::uint8_t>& master() const override { return grid_; }
  const RollingGrid<std::uint8_t>& obstacles() const override { return grid_; }
  std::uint32_t updates() const override { return 7; }

 private:
  RollingGrid<std::uint8_t> grid_;
};

TEST(CostmapInput, ReadsTheViewPublishedOnTheTopic) {
  Topic<CostmapMsg> topic;
  OneGridView view;
  CostmapInput in(topic);
  EXPECT_EQ(in.view(), nullptr);  // nothing published: no costmap is built
  topic.edit().view = &view;
  topic.publish(1);
  EXPECT_EQ(in.view(), &view);
  const std::uint32_t before = check_failures().count;
  EXPECT_EQ(&in.get(), &view);
  EXPECT_EQ(check_failures().count, before);
}

TEST(CostmapInput, NoViewWhereOneIsRequiredIsACheckedErrorWithAnEmptyView) {
  CostmapInput unwatched;
  EXPECT_EQ(unwatched.view(), nullptr);
  const std::uint32_t before = check_failures().count;
  const CostmapView& v = unwatched.get();
  EXPECT_EQ(check_failures().count, before + 1);
  EXPECT_EQ(v.updates(), 0u);  // never built: a mission waits for it as at start-up
  EXPECT_FALSE(v.master().ready());
  EXPECT_FALSE(v.obstacles().ready());
  EXPECT_EQ(v.walls(), nullptr);
}

}  // namespace
}  // namespace carril::fw
