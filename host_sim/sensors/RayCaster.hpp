#pragma once
// Closest hit of segments against a Box2D world, skipping one body: the fraction
// b2World::RayCast with a closest-hit callback finds, without its tree walk and virtual callbacks.
// Each fixture child's own b2Fixture::RayCast gives the same float fraction whatever maxFraction
// the tree passes it (maxFraction only culls), so the minimum over the fixtures a segment may
// touch is bit-identical. Candidates are culled by padded bounding boxes. Static bodies' fixtures,
// when there are many (map walls), are bucketed in a uniform grid walked along the segment; the
// grid is rebuilt only when they change. Moving bodies' fixtures are tested one by one.
#include <box2d/box2d.h>

#include <cstdint>
#include <vector>

namespace carril::sim {

class RayCaster {
 public:
  // Fraction returned by cast() when the segment hits nothing.
  static constexpr float kNoHit = 2.0F;
  // Candidates above which cast() walks a grid instead of testing each one. Measured with
  // callgrind, LidarSim::scan instructions, list vs grid: square.yaml (4 candidates) 0.49 G vs
  // 0.67 G; waypoints_vff.yaml (10) 0.87 G vs 1.05 G; taxi_city.yaml's map (21) 1.05 G vs 1.06 G;
  // goto_house_mcl.yaml's map (42) 0.39 G vs 0.27 G (2.55 G and 0.79 G with b2World::RayCast).
  static constexpr std::size_t kGridAbove = 24;

  // Collects every fixture child of every enabled body but `skip`, with its broad-phase bounding
  // box; call before each batch of casts (bodies may have moved since the last). The static
  // bodies' grid is rebuilt only when their fixtures or boxes differ from the last prepare().
  void prepare(const b2World& world, const b2Body* skip);
  // Fraction along p1 -> p2 of the closest hit (in [0, 1]), or kNoHit [1 = p2]; positions [m].
  float cast(const b2Vec2& p1, const b2Vec2& p2);
  // Number of candidate fixture children collected by the last prepare().
  std::size_t candidates() const { return statics_.size() + movers_.size(); }
  // True when cast() walks a grid over the static candidates (more than kGridAbove of them).
  bool uses_grid() const { return statics_.size() > kGridAbove; }
  // Grids built so far (a test sees the static grid kept across prepare() calls).
  std::uint64_t grid_builds() const { return grid_builds_; }

 private:
  struct Candidate {
    const b2Fixture* fixture;
    std::int32_t child;
    float cx, cy, hx, hy;  // padded bounding box: centre and half extents [m]
    bool operator==(const Candidate&) const = default;
  };
  struct Segment {
    b2RayCastInput input;
    float mx, my, ex, ey;    // bounding box: centre and half extents [m]
    float vx, vy, avx, avy;  // normal (-dy, dx) and its absolute value [m]
  };
  static Segment segment(const b2Vec2& p1, const b2Vec2& p2);
  static bool may_touch(const Candidate& c, const Segment& s);
  void test(const Candidate& c, const Segment& s, float& best) const;
  void build_grid();
  float cast_grid(const Segment& s, float best);

  std::vector<Candidate> statics_;  // fixtures of static bodies (the grid's, when it is used)
  std::vector<Candidate> movers_;   // fixtures of dynamic and kinematic bodies
  std::vector<Candidate> fresh_;    // this prepare()'s static fixtures, compared with statics_
  // Grid over the candidates' boxes: cell (i, j) holds items_[start_[j * nx_ + i] ..
  // start_[j * nx_ + i + 1]), indices into statics_.
  double gx_ = 0, gy_ = 0, cell_ = 1;  // lower corner and cell side [m]
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> start_, items_;
  std::vector<std::uint32_t> cursor_;  // per cell, where build_grid() puts the next item
  std::vector<std::uint32_t> stamp_;   // cast number that last tested each static candidate
  std::uint32_t casts_ = 0;
  std::uint64_t grid_builds_ = 0;
};

}  // namespace carril::sim
