#include "host_sim/world/SimWorld.hpp"

#include <algorithm>
#include <cmath>

#include "host_sim/world/MapWalls.hpp"

#include "firmware/core/Geometry.hpp"

namespace carril::sim {

// Counts each new contact that involves the robot (Box2D reports a contact once when it begins).
class SimWorld::ContactCounter : public b2ContactListener {
 public:
  explicit ContactCounter(SimWorld& w) : w_(w) {}
  void BeginContact(b2Contact* c) override {
    const b2Body* a = c->GetFixtureA()->GetBody();
    const b2Body* b = c->GetFixtureB()->GetBody();
    if (a != w_.robot_ && b != w_.robot_) return;
    const b2Body* other = a == w_.robot_ ? b : a;
    if (other->GetType() == b2_kinematicBody && !w_.robot_moving()) {
      ++w_.mover_contacts_;  // a mover walked into a robot that stood still
      return;
    }
    ++w_.collisions_;
    b2WorldManifold m;
    c->GetWorldManifold(&m);
    const b2Vec2 p = c->GetManifold()->pointCount > 0 ? m.points[0] : w_.robot_->GetPosition();
    w_.new_contacts_.push_back({p.x, p.y});
  }

 private:
  SimWorld& w_;
};

SimWorld::SimWorld(const Scenario& scenario)
    : scenario_(scenario),
      kin_(drive_geometry(scenario.robot)),
      world_(std::make_unique<b2World>(b2Vec2(0.0F, 0.0F))),
      contacts_(std::make_unique<ContactCounter>(*this)) {
  world_->SetContactListener(contacts_.get());
  for (const ObstacleSpec& o : scenario.obstacles) {
    if (o.shape == ObstacleShape::Box) {
      add_static_box(o.center.x, o.center.y, o.yaw_rad, o.size_x_m / 2, o.size_y_m / 2);
    } else {
      b2BodyDef bd;
      bd.position.Set(float(o.center.x), float(o.center.y));
      b2Body* body = world_->CreateBody(&bd);
      b2CircleShape c;
      c.m_radius = float(o.radius_m);
      body->CreateFixture(&c, 0.0F);
    }
  }
  for (const WallSpec& w : scenario.walls) {
    for (std::size_t i = 0; i + 1 < w.points.size(); ++i) {
      const Vec2 a = w.points[i], b = w.points[i + 1];
      const double len = std::hypot(b.x - a.x, b.y - a.y);
      if (len < 1e-6) continue;
      // Extend each segment by half the thickness so corners close.
      add_static_box((a.x + b.x) / 2, (a.y + b.y) / 2, std::atan2(b.y - a.y, b.x - a.x),
                     len / 2 + w.thickness_m / 2, w.thickness_m / 2);
    }
  }
  for (const MoverSpec& m : scenario.movers) add_mover(m);
  // The map's occupied cells, merged into few rectangles: one static body.
  if (scenario.map) add_map_walls(*world_, merge_occupied_cells(*scenario.map));
  const RobotSpec& r = scenario.robot;
  b2BodyDef bd;
  bd.type = b2_dynamicBody;
  bd.position.Set(float(r.start.x), float(r.start.y));
  bd.angle = float(r.start.yaw_rad);
  bd.bullet = true;  // no tunnelling through thin walls
  robot_ = world_->CreateBody(&bd);
  b2PolygonShape box;
  box.SetAsBox(float(r.length_m / 2), float(r.width_m / 2));
  b2CircleShape disc;
  disc.m_radius = float(r.width_m / 2);
  b2FixtureDef fd;
  fd.shape = r.round_body ? static_cast<const b2Shape*>(&disc) : &box;
  const double area =
      r.round_body ? fw::kPi * disc.m_radius * disc.m_radius : r.length_m * r.width_m;
  fd.density = float(r.mass_kg / area);
  fd.friction = 0.3F;
  robot_->CreateFixture(&fd);
  height_ = std::make_unique<HeightField>(scenario);
  terrain_ = std::make_unique<TerrainContact>(*height_, r);
  terrain_->reset(pose());
}

SimWorld::~SimWorld() {
  world_->SetContactListener(nullptr);
}

void SimWorld::add_static_box(double cx, double cy, double yaw, double hx, double hy) {
  b2BodyDef bd;
  bd.position.Set(float(cx), float(cy));
  bd.angle = float(yaw);
  b2Body* body = world_->CreateBody(&bd);
  b2PolygonShape s;
  s.SetAsBox(float(hx), float(hy));
  body->CreateFixture(&s, 0.0F);
}

void SimWorld::add_mover(const MoverSpec& m) {
  b2BodyDef bd;
  bd.type = b2_kinematicBody;
  bd.position.Set(float(m.path[0].x), float(m.path[0].y));
  bd.angle = float(std::atan2(m.path[1].y - m.path[0].y, m.path[1].x - m.path[0].x));
  b2Body* body = world_->CreateBody(&bd);
  b2PolygonShape box;
  box.SetAsBox(float(m.size_x_m / 2), float(m.size_y_m / 2));
  b2CircleShape disc;
  disc.m_radius = float(m.radius_m);
  if (m.shape == ObstacleShape::Box) {
    body->CreateFixture(&box, 0.0F);
  } else {
    body->CreateFixture(&disc, 0.0F);
  }
  movers_.push_back(body);
}

// Where a mover is `t` seconds after its start along its path (its end once there) [m].
static Vec2 along_path(const MoverSpec& m, double t) {
  double left = std::max(0.0, t - m.start_s) * m.speed_mps;
  for (std::size_t i = 0; i + 1 < m.path.size(); ++i) {
    const Vec2 a = m.path[i], b = m.path[i + 1];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    if (left <= len && len > 0.0)
      return {a.x + (b.x - a.x) * left / len, a.y + (b.y - a.y) * left / len};
    left -= len;
  }
  return m.path.back();
}

void SimWorld::drive_movers(double dt) {
  for (std::size_t i = 0; i < movers_.size(); ++i) {
    const Vec2 next = along_path(scenario_.movers[i], t_s_ + dt);
    const b2Vec2 now = movers_[i]->GetPosition();
    movers_[i]->SetLinearVelocity(
        b2Vec2(float((next.x - double(now.x)) / dt), float((next.y - double(now.y)) / dt)));
  }
}

Vec2 SimWorld::mover_position(std::size_t i) const {
  const b2Vec2 p = movers_[i]->GetPosition();
  return {double(p.x), double(p.y)};
}

bool SimWorld::robot_moving() const {
  // Its wheels turning, whatever a push does to the body: the robot is driving.
  for (int i = 0; i < kin_.wheel_count(); ++i) {
    if (std::fabs(wheel_speed_[std::size_t(i)]) > 0.05F) return true;
  }
  return false;
}

void SimWorld::set_wheel_targets(const float* radps) {
  for (int i = 0; i < kin_.wheel_count(); ++i) target_[std::size_t(i)] = radps[i];
}

void SimWorld::teleport(const Pose2& p) {
  robot_->SetTransform(b2Vec2(float(p.x), float(p.y)), float(p.yaw_rad));
  robot_->SetLinearVelocity(b2Vec2(0.0F, 0.0F));
  robot_->SetAngularVelocity(0.0F);
  terrain_->move_to(pose());
}

void SimWorld::step(double dt) {
  const LimitsSpec& lim = scenario_.robot.limits;
  // Wheel motors: follow the target within the acceleration and speed limits.
  const double dw_max = lim.max_wheel_accel_radps2 * dt;
  for (int i = 0; i < kin_.wheel_count(); ++i) {
    const auto k = std::size_t(i);
    const double want =
        std::clamp(double(target_[k]), -lim.max_wheel_speed_radps, lim.max_wheel_speed_radps);
    const double w =
        double(wheel_speed_[k]) + std::clamp(want - double(wheel_speed_[k]), -dw_max, dw_max);
    wheel_pos_[k] += 0.5 * (double(wheel_speed_[k]) + w) * dt;
    wheel_speed_[k] = float(w);
  }
  // The wheels set the body's velocity; contacts then constrain it inside the solver.
  const fw::Twist t = kin_.forward(wheel_speed_.data());
  const float yaw = robot_->GetAngle();
  const float c = std::cos(yaw), s = std::sin(yaw);
  robot_->SetLinearVelocity(b2Vec2(float(c * t.vx - s * t.vy), float(s * t.vx + c * t.vy)));
  robot_->SetAngularVelocity(float(t.wz));
  const b2Vec2 p0 = robot_->GetPosition();
  const float a0 = robot_->GetAngle();
  drive_movers(dt);
  world_->Step(float(dt), 8, 3);
  t_s_ += dt;
  // The ground: a step or slope beyond the robot's limits stops it where it was.
  const TerrainStep ts = terrain_->move_to(pose());
  if (ts.blocked) {
    robot_->SetTransform(p0, a0);
    robot_->SetLinearVelocity(b2Vec2(0.0F, 0.0F));
    robot_->SetAngularVelocity(0.0F);
  }
  if (ts.new_collision) {
    ++collisions_;
    new_contacts_.push_back({ts.where.x, ts.where.y});
  }
  if (ts.new_fall) ++falls_;
}

Pose2 SimWorld::pose() const {
  const b2Vec2 p = robot_->GetPosition();
  return {double(p.x), double(p.y), std::remainder(double(robot_->GetAngle()), 2.0 * fw::kPi)};
}

void SimWorld::body_velocity(double& vx, double& vy, double& wz) const {
  const b2Vec2 v = robot_->GetLinearVelocity();
  const double yaw = double(robot_->GetAngle());
  const double c = std::cos(yaw), s = std::sin(yaw);
  vx = c * double(v.x) + s * double(v.y);
  vy = -s * double(v.x) + c * double(v.y);
  wz = double(robot_->GetAngularVelocity());
}

std::vector<ContactStart> SimWorld::take_new_contacts() {
  std::vector<ContactStart> out;
  out.swap(new_contacts_);
  return out;
}

}  // namespace carril::sim

// Box2D times every step and every time of impact with b2Timer (for b2World::GetProfile and its
// TOI statistics), a dozen gettimeofday calls per step: about 2 % of a square run. The simulator
// reads neither, so every program that links SimWorld defines b2Timer as a timer that never reads
// the clock. libbox2d calls b2Timer's exported functions through its PLT, so these definitions
// take the place of its own (ELF symbol interposition); the step itself is unchanged.
// SimWorldTest.Box2DsStepTimerIsTheSimulatorsOwn checks that they are the ones in use.
b2Timer::b2Timer() : m_start_sec(0), m_start_usec(0) {}
void b2Timer::Reset() {}
float b2Timer::GetMilliseconds() const {
  return 0.0F;
}
