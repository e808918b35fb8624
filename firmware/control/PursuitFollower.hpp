#pragma once
// Minimal line follower for the walking skeleton: pure pursuit of the tape point nearest the
// look-ahead distance, slowing in curves. The line-tracking mission replaces it behind the same
// inputs (a TapeObservation) and output (a Twist).
#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/perception/TapeScanner.hpp"

namespace carril::fw {

class PursuitFollower {
 public:
  PursuitFollower(const FirmwareConfig::Follower& cfg, double lookahead_m, double speed_mps)
      : cfg_(cfg), lookahead_m_(lookahead_m), speed_mps_(speed_mps) {}

  // Twist toward the tape; `obs.line_seen` must be true.
  Twist follow(const TapeObservation& obs) const;
  // Drive to a floor point given in the robot frame, slowing to stop on it.
  Twist approach(const Vec2& target, bool holonomic) const;
  double lookahead_m() const { return lookahead_m_; }

 private:
  FirmwareConfig::Follower cfg_;
  double lookahead_m_;
  double speed_mps_;
};

}  // namespace carril::fw
