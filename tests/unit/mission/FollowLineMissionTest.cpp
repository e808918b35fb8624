// FollowLineMission through the Mission interface: it reads its inputs from the bus, keeps the
// tape and the end mark it saw, and reports generic status, state and phase names and counters.
#include "firmware/mission/FollowLineMission.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <string>

namespace carril::fw {
namespace {

struct Rig {
  Topic<OdometryMsg> odom;
  Topic<LineObservation> line;
  Topic<ObstacleField> obstacles{Footprint{0.25, 0.25}, 0.0, 0.0, 0.0};
  FollowLineConfig cfg;
  FollowLineMission mission{cfg, Footprint{0.25, 0.25}, false, true, odom, line, obstacles};
  MissionContext ctx;

  // A frame whose tape runs straight from `from` to `to` (robot frame) in `n` steps; `sure`: a
  // blob large enough to be tape on its own, otherwise a piece.
  void see(hal::TimeNs t, const Vec2& from, const Vec2& to, int n, bool sure) {
    LineObservation& o = line.edit();
    o.detection.detected = true;
    o.detection.sure = sure;
    o.detection.centerline_floor.clear();
    for (int i = 0; i <= n; ++i) {
      o.detection.centerline_floor.push_back(from + (to - from) * (double(i) / n));
    }
    o.pose = odom.get().pose;
    line.publish(t);
  }
  // Straight tape from 0.3 m to 1.2 m ahead, on the centre line, 10 points.
  void see_tape(hal::TimeNs t) { see(t, Vec2(0.3, 0.0), Vec2(1.2, 0.0), 9, true); }
  // Only a piece smaller than tape on its own, 4 points.
  void see_piece(hal::TimeNs t, const Vec2& from, const Vec2& to) { see(t, from, to, 3, false); }
  MissionOutput step(double t_s) {
    ctx.t_s = t_s;
    ctx.dt_s = 0.01;
    ctx.drives_ready = true;
    return mission.update(ctx);
  }
};

TEST(FollowLineMissionTest, StartsWaitingThenFollowsTapeItStandsOn) {
  Rig r;
  r.mission.enter(r.ctx);
  EXPECT_STREQ(r.mission.name(), "follow_line");
  MissionState s = r.mission.state();
  EXPECT_EQ(s.status, MissionStatus::Starting);
  EXPECT_STREQ(s.name, "START");
  EXPECT_STREQ(s.phase, "wait");
  // Devices up: a scan and a frame arrived.
  r.obstacles.publish(1);
  r.see_tape(1);
  r.step(0.0);  // wait -> find
  r.see_tape(2);
  r.step(0.01);  // on the tape: follow
  s = r.mission.state();
  EXPECT_EQ(s.status, MissionStatus::Active);
  EXPECT_STREQ(s.name, "FOLLOW");
  EXPECT_TRUE(s.on_path);
  EXPECT_EQ(r.mission.tape().points().size(), 10U);  // the frames went into the tape memory
  r.see_tape(3);
  const MissionOutput o = r.step(0.02);
  EXPECT_TRUE(o.motion.guarded);  // following: the runner's obstacle stop applies
  EXPECT_GT(o.motion.twist.vx, 0.0);
}

TEST(FollowLineMissionTest, WithoutDevicesItFailsWithTheFaultThatSaysWhich) {
  Rig r;
  r.mission.enter(r.ctx);
  r.ctx.t_s = 0.0;
  MissionOutput o;
  for (int i = 0; i < 400 && o.fault == Fault::None; ++i) {
    r.ctx.t_s = 0.01 * i;
    r.ctx.drives_ready = false;
    o = r.mission.update(r.ctx);
  }
  EXPECT_EQ(o.fault, Fault::DriveEnableTimeout);
  EXPECT_EQ(r.mission.state().status, MissionStatus::Failed);
  EXPECT_STREQ(r.mission.state().name, "FAULT");
}

TEST(FollowLineMissionTest, CountsUnderTheirNames) {
  Rig r;
  MissionCounters c;
  r.mission.counters(c);
  ASSERT_EQ(c.size(), 6U);
  const char* names[] = {"line_lost_events",  "line_reacquired_events", "reversed_sightings",
                         "obstacles_avoided", "tape_pieces_taken",      "tape_pieces_refused"};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_STREQ(c[i].name, names[i]);
    EXPECT_EQ(c[i].value, 0U);
  }
}

// Issue 46 item 4: a piece of tape too small to count on its own (worn tape between gaps) is
// tape where it continues the remembered tape, past a gap, and is then remembered; beside the
// tape's line it is a speck: refused, counted, and it neither starts a follow nor enters memory.
TEST(FollowLineMissionTest, APieceCountsOnlyWhereItContinuesTheRememberedTape) {
  Rig r;
  r.mission.enter(r.ctx);
  r.obstacles.publish(1);
  // Before any tape is remembered a piece is not tape: START does not leave its search for it.
  r.see_piece(1, Vec2(0.3, 0.0), Vec2(0.45, 0.0));
  r.step(0.0);
  r.see_piece(2, Vec2(0.3, 0.0), Vec2(0.45, 0.0));
  r.step(0.01);
  EXPECT_STREQ(r.mission.state().name, "START");
  EXPECT_TRUE(r.mission.tape().empty());
  EXPECT_EQ(r.mission.pieces_refused(), 2U);
  r.see_tape(3);
  r.step(0.02);
  ASSERT_STREQ(r.mission.state().name, "FOLLOW");
  const std::size_t remembered = r.mission.tape().points().size();
  // Past a 15 cm gap beyond memory's end (1.2 m): taken, and memory now reaches 1.59 m.
  r.see_piece(4, Vec2(1.35, 0.0), Vec2(1.59, 0.0));
  r.step(0.03);
  EXPECT_EQ(r.mission.pieces_taken(), 1U);
  EXPECT_GT(r.mission.tape().points().size(), remembered);
  EXPECT_NEAR(r.mission.tape().points().back().x(), 1.59, 1e-9);
  // 12 cm beside the line: refused, memory unchanged.
  const std::size_t before = r.mission.tape().points().size();
  r.see_piece(5, Vec2(1.65, 0.12), Vec2(1.89, 0.12));
  r.step(0.04);
  EXPECT_EQ(r.mission.pieces_refused(), 3U);
  EXPECT_EQ(r.mission.tape().points().size(), before);
  EXPECT_NEAR(r.mission.tape().points().back().x(), 1.59, 1e-9);
  MissionCounters c;
  r.mission.counters(c);
  EXPECT_EQ(c[4].value, 1U);
  EXPECT_EQ(c[5].value, 3U);
}

TEST(FollowLineMissionTest, ConfigValidateNamesNestedFields) {
  FollowLineConfig c;
  EXPECT_TRUE(c.validate().is_ok());
  c.tape_preview_m = -1.0;
  EXPECT_NE(std::string(c.validate().message()).find("follow_line.tape_preview_m: -1 m"),
            std::string::npos)
      << c.validate().message();
}

}  // namespace
}  // namespace carril::fw
