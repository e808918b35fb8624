#include "firmware/mission/LostExplorer.hpp"

#include <algorithm>
#include <cmath>

namespace carril::fw {

namespace {
constexpr double kFacedRad = 0.05;    // a leg's heading is faced within this [rad]
constexpr double kHeadingGain = 1.5;  // heading hold on a leg [1/s]
// A leg does not go back the way the last one came (within this of its reverse) while another
// heading has room: what lies there has been seen [rad].
constexpr double kBackRad = kPi / 3.0;
// Backing along a leg: it stops this close to the leg's start, or to what is behind [m].
constexpr double kLegStartM = 0.02;
constexpr double kBehindStopM = 0.15;
}  // namespace

Status LostExploreConfig::validate() const {
  return Checks("runner.lost_explore")
      .range("speed_mps", speed_mps, 0.0, 1.0, "m/s")
      .range("after_turn_rad", after_turn_rad, 0.0, 100.0, "rad")
      .range("leg_m", leg_m, 0.1, 50.0, "m")
      .range("min_free_m", min_free_m, 0.1, 50.0, "m")
      .range("stop_free_m", stop_free_m, 0.05, 50.0, "m")
      .fail_if(stop_free_m >= min_free_m, "stop_free_m", "must be below min_free_m")
      .result();
}

void LostExplorer::Best::see(double free, double heading) {
  if (free > free_m) {
    free_m = free;
    yaw = run_start = heading;
    in_run = true;
  } else if (free == free_m && in_run) {
    yaw = wrap_angle(run_start + 0.5 * wrap_angle(heading - run_start));
  } else {
    in_run = false;
  }
}

void LostExplorer::reset() {
  have_leg_ = false;
  have_yaw_ = false;
  start_turn();
}

Twist LostExplorer::back_along_leg(const Pose2& odom) const {
  Twist t;
  t.vx = -cfg_.speed_mps;
  t.wz = std::clamp(kHeadingGain * wrap_angle(last_leg_yaw_ - odom.yaw), -turn_radps_, turn_radps_);
  return t;
}

void LostExplorer::start_turn() {
  phase_ = Phase::Turn;
  backing_ = false;
  turned_rad_ = 0.0;
  ahead_ = Best{};
  any_ = Best{};
}

double LostExplorer::from_leg_start_m(const Pose2& odom) const {
  return std::hypot(odom.x - leg_start_.x(), odom.y - leg_start_.y());
}

double LostExplorer::along_leg_m(const Pose2& odom) const {
  return (odom.x - leg_start_.x()) * std::cos(last_leg_yaw_) +
         (odom.y - leg_start_.y()) * std::sin(last_leg_yaw_);
}

Twist LostExplorer::step(const Pose2& odom, bool can_turn, double free_m, double behind_m) {
  const double dyaw = have_yaw_ ? std::fabs(wrap_angle(odom.yaw - last_yaw_)) : 0.0;
  last_yaw_ = odom.yaw;
  have_yaw_ = true;
  Twist t;
  switch (phase_) {
    case Phase::Turn: {
      if (backing_) {
        // Backed all the way to where the leg began, where it turned all round before. Something
        // now behind it: it waits, still backing, unless there is room to turn after all.
        if (along_leg_m(odom) > kLegStartM) {
          if (behind_m >= kBehindStopM) return back_along_leg(odom);
          if (!can_turn) return t;
        }
        backing_ = false;
        // Out of the dead end: the next leg does not go back into it.
        last_leg_yaw_ = wrap_angle(last_leg_yaw_ + kPi);
      }
      turned_rad_ += dyaw;
      const bool back =
          have_leg_ && std::fabs(wrap_angle(odom.yaw - last_leg_yaw_ - kPi)) < kBackRad;
      // Beyond a leg's length every corridor is as good: the first seen wins, not one that looks
      // out of the building where no beam returns.
      const double useful = std::fmin(free_m, cfg_.leg_m + cfg_.stop_free_m);
      any_.see(useful, odom.yaw);
      ahead_.see(back ? -1.0 : useful, odom.yaw);
      if (cfg_.speed_mps > 0.0 && turned_rad_ >= cfg_.after_turn_rad) {
        // Back the way it came only where no other way has room (a dead end).
        const Best& b = ahead_.free_m >= cfg_.min_free_m ? ahead_ : any_;
        if (b.free_m >= cfg_.min_free_m) {
          leg_yaw_ = b.yaw;
          phase_ = Phase::Face;
          return step(odom, can_turn, free_m, behind_m);
        }
      }
      if (can_turn) {
        t.wz = turn_radps_;
      } else if (have_leg_ && cfg_.speed_mps > 0.0 && behind_m >= kBehindStopM &&
                 from_leg_start_m(odom) > kLegStartM) {
        // The last leg ended where there is no room to turn: standing still there it would wait
        // for ever.
        backing_ = true;
        ++backs_;
        return back_along_leg(odom);
      }
      return t;
    }
    case Phase::Face: {
      const double e = wrap_angle(leg_yaw_ - odom.yaw);
      if (std::fabs(e) > kFacedRad) {
        if (can_turn) t.wz = e > 0.0 ? turn_radps_ : -turn_radps_;
        return t;
      }
      if (free_m < cfg_.min_free_m) {  // what was free is no longer: look round again
        start_turn();
        return t;
      }
      phase_ = Phase::Drive;
      leg_start_ = Vec2{odom.x, odom.y};
      last_leg_yaw_ = leg_yaw_;
      have_leg_ = true;
      ++legs_;
      [[fallthrough]];
    }
    case Phase::Drive: {
      if (from_leg_start_m(odom) >= cfg_.leg_m || free_m < cfg_.stop_free_m) {
        start_turn();
        return t;
      }
      t.vx = cfg_.speed_mps;
      const double w = kHeadingGain * wrap_angle(last_leg_yaw_ - odom.yaw);
      t.wz = std::clamp(w, -turn_radps_, turn_radps_);
      return t;
    }
  }
  return t;
}

}  // namespace carril::fw
