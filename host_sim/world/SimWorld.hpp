#pragma once
// The Box2D world of one run: static obstacles and walls from the scenario, and the robot as a
// dynamic body moved through its wheels. Top-down, no gravity. Metres, radians, seconds.
#include <box2d/box2d.h>

#include <array>
#include <memory>
#include <vector>

#include "firmware/kinematics/DriveKinematics.hpp"
#include "hal/Types.hpp"
#include "host_sim/scenario/Scenario.hpp"
#include "host_sim/world/HeightField.hpp"
#include "host_sim/world/TerrainContact.hpp"
#include "loader/FirmwareConfigBuilder.hpp"

namespace carril::sim {

struct ContactStart {
  double x = 0.0, y = 0.0;  // world point where the robot touched something [m]
};

class SimWorld {
 public:
  explicit SimWorld(const Scenario& scenario);
  ~SimWorld();
  SimWorld(const SimWorld&) = delete;
  SimWorld& operator=(const SimWorld&) = delete;

  // Wheel motor targets for the next steps [rad/s]; each wheel follows within its speed and
  // acceleration limits.
  void set_wheel_targets(const float* radps);
  // Advances the physics by dt seconds.
  void step(double dt_s);

  Pose2 pose() const;
  // Moves the robot to p at rest (a kidnap: lifted and set down; the wheels do not turn).
  void teleport(const Pose2& p);
  // True body-frame velocity from the physics (differs from the wheels' when blocked) [m/s, rad/s].
  void body_velocity(double& vx, double& vy, double& wz) const;
  int wheel_count() const { return kin_.wheel_count(); }
  float wheel_speed(int i) const { return wheel_speed_[std::size_t(i)]; }    // [rad/s]
  double wheel_position(int i) const { return wheel_pos_[std::size_t(i)]; }  // [rad]

  // Contacts while the robot was moving (its own doing), with anything, movers included.
  int collisions() const { return collisions_; }
  // Contacts a mover made with the robot standing still (not the robot's doing).
  int mover_contacts() const { return mover_contacts_; }
  // Where mover i is now [m] (the scenario's movers, in order).
  Vec2 mover_position(std::size_t i) const;
  // Drops beyond the robot's terrain_limits.max_step_down_m driven off (each also a collision).
  int falls() const { return falls_; }
  // Roll, pitch (positive nose up) and height of the body from the ground under its wheels.
  Attitude attitude() const { return terrain_->attitude(); }
  // The surface (terrain and obstacle tops), for the 3D lidar.
  const HeightField& height_field() const { return *height_; }
  // Contact starts since the last call (for plotting).
  std::vector<ContactStart> take_new_contacts();

  const b2World& world() const { return *world_; }
  const b2Body* robot_body() const { return robot_; }

 private:
  class ContactCounter;
  void add_static_box(double cx, double cy, double yaw, double hx, double hy);
  void add_mover(const MoverSpec& m);
  // Sets each mover's velocity so that it reaches its place on its path at t_s_ + dt.
  void drive_movers(double dt);
  bool robot_moving() const;

  const Scenario& scenario_;
  fw::DriveKinematics kin_;
  std::unique_ptr<b2World> world_;
  std::unique_ptr<ContactCounter> contacts_;
  b2Body* robot_ = nullptr;
  std::array<float, hal::kMaxWheels> target_{};
  std::array<float, hal::kMaxWheels> wheel_speed_{};
  std::array<double, hal::kMaxWheels> wheel_pos_{};
  int collisions_ = 0;
  int mover_contacts_ = 0;
  int falls_ = 0;
  double t_s_ = 0.0;             // physics time [s]
  std::vector<b2Body*> movers_;  // kinematic, one per scenario mover
  std::unique_ptr<HeightField> height_;
  std::unique_ptr<TerrainContact> terrain_;
  std::vector<ContactStart> new_contacts_;
};

// The firmware configuration's own mapping, so the simulated wheels are the ones it drives.
using loader::drive_geometry;

}  // namespace carril::sim
