#pragma once
// What a robot that cannot localise does with its time. It turns in place, so that a lidar that
// sees only ahead shows the filter the whole room. A view can fit several places alike (inside
// one of a row of alike aisles, every aisle looks the same), and turning there shows nothing new
// however long it goes on: so once a whole turn has not found it, it drives a short leg toward
// where it saw the longest free corridor during that turn, slowly and only while the corridor
// stays clear, and looks round again from there. A leg that ends where there is no room to turn
// is backed along to its start (it was just driven, so it is free, and the robot turned all round
// there) while the way behind stays clear: standing still, it would wait for ever. Pure logic: the
// mission runner hands it the odometry pose and what the obstacle field says, and applies the
// room-to-turn check itself.
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "firmware/core/Status.hpp"

namespace carril::fw {

struct LostExploreConfig {
  double speed_mps = 0.0;          // a leg's speed; 0: it only turns, never drives [m/s]
  double after_turn_rad = 6.2832;  // turned this far in place, still lost, before a leg [rad]
  double leg_m = 2.0;              // a leg ends after this far [m]
  double min_free_m = 1.0;         // a heading is worth a leg only with this much free ahead [m]
  double stop_free_m = 0.6;        // a leg ends once the corridor ahead is shorter than this [m]

  Status validate() const;
  bool operator==(const LostExploreConfig&) const = default;
};

class LostExplorer {
 public:
  enum class Phase : std::uint8_t { Turn, Face, Drive };

  // `turn_radps`: the rate of the look-round turn and of facing a leg's heading [rad/s].
  LostExplorer(const LostExploreConfig& cfg, double turn_radps)
      : cfg_(cfg), turn_radps_(turn_radps) {}

  // Found again: the next loss starts with a whole turn from where it then stands.
  void reset();
  // The motion for this tick. `odom`: the odometry pose (not the lost map pose); `can_turn`: room
  // to turn in place all round; `free_m`: the free corridor ahead of the front bumper [m];
  // `behind_m`: the same behind the rear bumper (0: unknown, it never backs) [m].
  Twist step(const Pose2& odom, bool can_turn, double free_m, double behind_m = 0.0);

  Phase phase() const { return phase_; }
  std::uint32_t legs() const { return legs_; }    // legs started since construction
  std::uint32_t backs() const { return backs_; }  // legs backed along for room to turn
  // Whether it drives legs (speed_mps > 0); without legs, what step() asks for does not depend
  // on free_m.
  bool drives() const { return cfg_.speed_mps > 0.0; }

 private:
  void start_turn();
  // Backing toward the last leg's start, holding its heading.
  Twist back_along_leg(const Pose2& odom) const;
  // Straight-line distance from where the current leg began [m].
  double from_leg_start_m(const Pose2& odom) const;
  // How far along the leg's heading it is from where the leg began [m]. Backing ends where this
  // reaches the start: a robot a few cm to the side of its track never comes within a small
  // circle round the start, and would back on past it until something stood behind it.
  double along_leg_m(const Pose2& odom) const;

  // The longest corridor seen in a look-round, and the middle of the first run of headings that
  // saw it (a heading at the edge of an opening may no longer fit through once faced).
  struct Best {
    double free_m = -1.0;    // [m]
    double yaw = 0.0;        // [rad]
    double run_start = 0.0;  // [rad]
    bool in_run = false;
    void see(double free, double heading);
  };

  LostExploreConfig cfg_;
  double turn_radps_;
  Phase phase_ = Phase::Turn;
  bool have_yaw_ = false;
  double last_yaw_ = 0.0;
  double turned_rad_ = 0.0;    // turned in place since the look-round began [rad]
  Best ahead_;                 // in it, not back the way the last leg came
  Best any_;                   // in it, every heading
  double leg_yaw_ = 0.0;       // the heading of the leg it faces or drives [rad]
  bool have_leg_ = false;      // a leg was driven since the last reset
  double last_leg_yaw_ = 0.0;  // that leg's heading [rad]
  Vec2 leg_start_{};           // where the current leg began (odometry frame) [m]
  bool backing_ = false;       // backing along the last leg (no room to turn where it ended)
  std::uint32_t legs_ = 0, backs_ = 0;
};

}  // namespace carril::fw
