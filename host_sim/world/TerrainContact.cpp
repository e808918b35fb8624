#include "host_sim/world/TerrainContact.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "firmware/core/Geometry.hpp"

namespace carril::sim {

namespace {
constexpr double kUnlatchM = 0.02;  // a block is a new contact once the robot was this far [m]
// Rest heights are compared with this tolerance, so rounding never makes a step [m].
constexpr double kEpsM = 1e-9;

double dist(Vec2 a, Vec2 b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}
}  // namespace

TerrainContact::TerrainContact(const HeightField& field, const RobotSpec& robot)
    : field_(field),
      half_base_(robot.wheelbase_m / 2.0),
      half_track_(robot.track_m / 2.0),
      r_(robot.wheel_radius_m),
      max_tan_slope_(std::tan(robot.terrain_limits.max_slope_deg * fw::kPi / 180.0)),
      max_up_(robot.terrain_limits.max_step_up_m),
      max_down_(robot.terrain_limits.max_step_down_m),
      wheelbase_(robot.wheelbase_m),
      track_(robot.track_m) {}

TerrainContact::Rest TerrainContact::rest(const Pose2& p, int wheel) const {
  const double c = std::cos(p.yaw_rad), s = std::sin(p.yaw_rad);
  const double bx = wheel < 2 ? half_base_ : -half_base_;
  const double by = wheel % 2 == 0 ? half_track_ : -half_track_;
  Rest best;
  bool first = true;
  for (const double k : {0.0, 0.5, -0.5, 1.0, -1.0}) {
    const double lx = bx + k * r_;
    const Vec2 q{p.x + c * lx - s * by, p.y + s * lx + c * by};
    const GroundSample g = field_.ground_sample(q.x, q.y);
    if (first || g.z_m > best.z + kEpsM) {
      best = {g.z_m, std::abs(g.dzdx * c + g.dzdy * s), q};
      first = false;
    }
  }
  return best;
}

void TerrainContact::reset(const Pose2& pose) {
  pose_ = pose;
  for (int i = 0; i < kWheels; ++i) {
    const Rest r = rest(pose, i);
    z_[std::size_t(i)] = r.z;
    slope_[std::size_t(i)] = r.slope;
  }
  blocked_latch_ = fall_latch_ = false;
}

TerrainStep TerrainContact::move_to(const Pose2& pose) {
  TerrainStep out;
  std::array<Rest, kWheels> next;
  bool fell = false;
  for (int i = 0; i < kWheels; ++i) {
    const auto k = std::size_t(i);
    next[k] = rest(pose, i);
    const double dz = next[k].z - z_[k];
    const bool step_up = dz > max_up_ + kEpsM;
    const bool too_steep = next[k].slope > max_tan_slope_ && next[k].slope > slope_[k] + kEpsM;
    if (step_up || too_steep) {
      out.blocked = true;
      out.where = next[k].at;
    } else if (-dz > max_down_ + kEpsM && !fell) {
      fell = true;
      out.where = next[k].at;
    }
  }
  if (out.blocked) {
    if (!blocked_latch_) {
      blocked_latch_ = true;
      block_xy_ = {pose_.x, pose_.y};
      out.new_collision = true;
    }
    return out;
  }
  pose_ = pose;
  for (std::size_t k = 0; k < z_.size(); ++k) {
    z_[k] = next[k].z;
    slope_[k] = next[k].slope;
  }
  const Vec2 xy{pose.x, pose.y};
  if (blocked_latch_ && dist(xy, block_xy_) > kUnlatchM) blocked_latch_ = false;
  // The whole robot is past the edge once it has moved its wheelbase and a tyre further.
  if (fall_latch_ && dist(xy, fall_xy_) > wheelbase_ + 2.0 * r_) fall_latch_ = false;
  if (fell && !fall_latch_) {
    fall_latch_ = true;
    fall_xy_ = xy;
    out.new_fall = true;
    out.new_collision = true;
  }
  return out;
}

Attitude TerrainContact::attitude() const {
  // Wheels: 0 front-left, 1 front-right, 2 rear-left, 3 rear-right.
  const double front = (z_[0] + z_[1]) / 2.0, rear = (z_[2] + z_[3]) / 2.0;
  const double left = (z_[0] + z_[2]) / 2.0, right = (z_[1] + z_[3]) / 2.0;
  Attitude a;
  a.pitch_rad = std::atan2(front - rear, wheelbase_);
  a.roll_rad = std::atan2(left - right, track_);
  a.z_m = (front + rear) / 2.0;
  return a;
}

}  // namespace carril::sim
