#pragma once
// Closest hit of segments against a Box2D world, skipping one body: the fraction
// b2World::RayCast with a closest-hit callback finds, without its tree walk and virtual callbacks.
// Each fixture child's own b2Fixture::RayCast gives the same float fraction whatever maxFraction
// the tree passes it (maxFraction only culls), so the minimum over the fixtures a segment may
// touch is bit-identical. Candidates are culled by padded bounding boxes; with many of them (map
// walls) they are bucketed in a uniform grid walked along the segment.
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
  // box; call before each batch of casts (bodies may have moved since the last).
  void prepare(const b2World& world, const b2Body* skip);
  // Fraction along p1 -> p2 of the closest hit (in [0, 1]), or kNoHit [1 = p2]; positions [m].
  float cast(const b2Vec2& p1, const b2Vec2& p2);
  // Number of candidate fixture children collected by the last prepare().
  std::size_t candidates() const { return cands_.size(); }

 private:
  struct Candidate {
    const b2Fixture* fixture;
    std::int32_t child;
    float cx, cy, hx, hy;  // padded bounding box: centre and half extents [m]
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
  float cast_grid(const Segment& s);

  std::vector<Candidate> cands_;
  // Grid over the candidates' boxes: cell (i, j) holds items_[start_[j * nx_ + i] ..
  // start_[j * nx_ + i + 1]), indices into cands_.
  double gx_ = 0, gy_ = 0, cell_ = 1;  // lower corner and cell side [m]
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> start_, items_;
  std::vector<std::uint32_t> stamp_;  // cast number that last tested each candidate
  std::uint32_t casts_ = 0;
};

}  // namespace carril::sim
