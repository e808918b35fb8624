// The simulated camera puts floor points on the pixels a pinhole camera would. Expected pixels
// are derived here by hand from the mounting geometry, not through fw::CameraModel.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <string>

#include "hal/Types.hpp"
#include "host_sim/sensors/CameraRenderer.hpp"
#include "tests/support/SimTestScenario.hpp"

namespace carril::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A yellow dot of radius 1.5 cm on a grey floor at world point (mx, my).
Scenario dot_scenario(double mx, double my) {
  char yaml[1024];
  std::snprintf(yaml, sizeof yaml, R"(
name: camera_dot
duration_s: 1
floor: {color: [100, 100, 100]}
robot: {preset: campero}
mission: {type: follow_line, strategy: marks, line_color: white}
lines: [{color: white, width_m: 0.05, points: [[-20, -20], [-19, -20]]}]
marks: [{color: yellow, x: %.6f, y: %.6f, radius_m: 0.015}]
)",
                mx, my);
  return test::load_text(yaml);
}

// Centroid of the yellow pixels.
bool yellow_centroid(const hal::CameraFrame& f, double& u, double& v, int& n) {
  double su = 0, sv = 0;
  n = 0;
  for (int y = 0; y < f.height; ++y) {
    for (int x = 0; x < f.width; ++x) {
      const std::uint8_t* p = f.pixel(x, y);
      if (p[0] < 50 && p[1] > 200 && p[2] > 200) {
        su += x;
        sv += y;
        ++n;
      }
    }
  }
  if (n == 0) return false;
  u = su / n;
  v = sv / n;
  return true;
}

TEST(CameraRendererTest, FloorPointOnOpticalAxisLandsOnImageCentre) {
  // campero camera: x 0.49, z 0.90, tilt 55 deg. The optical axis meets the floor at
  // x = 0.49 + 0.90 / tan(55 deg) = 1.1202 m straight ahead; it images at the principal point
  // ((640-1)/2, (480-1)/2) = (319.5, 239.5).
  const double ax = 0.49 + 0.90 / std::tan(55 * kDeg);
  const Scenario s = dot_scenario(ax, 0.0);
  CameraRenderer cam(s, 1);
  auto frame = std::make_unique<hal::CameraFrame>();
  cam.render({0.0, 0.0, 0.0}, *frame);
  ASSERT_EQ(frame->width, 640);
  ASSERT_EQ(frame->height, 480);
  double u = 0, v = 0;
  int n = 0;
  ASSERT_TRUE(yellow_centroid(*frame, u, v, n));
  EXPECT_GT(n, 20);
  EXPECT_NEAR(u, 319.5, 0.5);
  EXPECT_NEAR(v, 239.5, 0.5);
}

TEST(CameraRendererTest, OffAxisPointMatchesPinholeByHand) {
  // Robot at (2, 1) facing +y (yaw 90 deg). A dot 1.3 m ahead and 0.2 m to its left is at world
  // (2 - 0.2, 1 + 1.3) = (1.8, 2.3). In the camera: lateral X = -0.2 (image right is robot -y);
  // relative to the optical centre, forward d = 1.3 - 0.49 = 0.81, down h = 0.90.
  // Depth along the axis Z = d cos(t) + h sin(t); image-down Y = -d sin(t) + h cos(t)... with the
  // camera's y axis (-sin t, 0, -cos t) applied to (d, 0.2, -h): Y = -d sin t + h cos t.
  // f = 320 / tan(54.2/2 deg).
  const double t = 55 * kDeg, d = 0.81, h = 0.90, lat = -0.2;
  const double z = d * std::cos(t) + h * std::sin(t);
  const double y = -d * std::sin(t) + h * std::cos(t);
  const double f = 320.0 / std::tan(54.2 / 2 * kDeg);
  const double u_exp = f * lat / z + 319.5, v_exp = f * y / z + 239.5;
  const Scenario s = dot_scenario(1.8, 2.3);
  CameraRenderer cam(s, 1);
  auto frame = std::make_unique<hal::CameraFrame>();
  cam.render({2.0, 1.0, 90 * kDeg}, *frame);
  double u = 0, v = 0;
  int n = 0;
  ASSERT_TRUE(yellow_centroid(*frame, u, v, n));
  EXPECT_LT(u, 319.5);  // left of the robot is left in the image
  EXPECT_NEAR(u, u_exp, 0.5);
  EXPECT_NEAR(v, v_exp, 0.5);
}

TEST(CameraRendererTest, PointBehindCameraIsNotDrawn) {
  const Scenario s = dot_scenario(-1.0, 0.0);
  CameraRenderer cam(s, 1);
  auto frame = std::make_unique<hal::CameraFrame>();
  cam.render({0.0, 0.0, 0.0}, *frame);
  double u = 0, v = 0;
  int n = 0;
  EXPECT_FALSE(yellow_centroid(*frame, u, v, n));
  EXPECT_EQ(frame->pixel(0, 0)[0], 100);  // floor colour everywhere
}

TEST(CameraRendererTest, NoiseIsSeededAndDeterministic) {
  Scenario s = dot_scenario(1.1, 0.0);
  s.robot.camera.noise_std = 4.0;
  auto a = std::make_unique<hal::CameraFrame>(), b = std::make_unique<hal::CameraFrame>(),
       c = std::make_unique<hal::CameraFrame>();
  CameraRenderer ra(s, 7), rb(s, 7), rc(s, 8);
  ra.render({0, 0, 0}, *a);
  rb.render({0, 0, 0}, *b);
  rc.render({0, 0, 0}, *c);
  const std::size_t n = 640 * 480 * 3;
  EXPECT_EQ(0, std::memcmp(a->bgr.data(), b->bgr.data(), n));
  EXPECT_NE(0, std::memcmp(a->bgr.data(), c->bgr.data(), n));
  // Noise is zero-mean around the noise-free image (floor and its texture).
  s.robot.camera.noise_std = 0.0;
  auto clean = std::make_unique<hal::CameraFrame>();
  CameraRenderer(s, 7).render({0, 0, 0}, *clean);
  double sum = 0;
  for (int x = 0; x < 640; ++x) sum += double(a->pixel(x, 0)[1]) - double(clean->pixel(x, 0)[1]);
  EXPECT_NEAR(sum / 640, 0.0, 1.0);
}

// Largest minus smallest green value over the frame.
int green_spread(const hal::CameraFrame& f) {
  int lo = 255, hi = 0;
  for (int v = 0; v < f.height; ++v) {
    for (int u = 0; u < f.width; ++u) {
      lo = std::min(lo, int(f.pixel(u, v)[1]));
      hi = std::max(hi, int(f.pixel(u, v)[1]));
    }
  }
  return hi - lo;
}

TEST(CameraRendererTest, FloorIsTexturedFixedInTheWorld) {
  // Nothing but floor in view: the texture's speckles are 15% brighter or darker than it.
  const Scenario s = dot_scenario(-5.0, 0.0);
  auto a = std::make_unique<hal::CameraFrame>(), b = std::make_unique<hal::CameraFrame>(),
       c = std::make_unique<hal::CameraFrame>();
  CameraRenderer(s, 1).render({0, 0, 0}, *a);
  EXPECT_GE(green_spread(*a), 25);
  EXPECT_LE(green_spread(*a), 31);  // 100 x 0.85 .. 100 x 1.15
  // The same floor whatever the seed: a property of the world, not of the noise.
  CameraRenderer(s, 2).render({0, 0, 0}, *b);
  EXPECT_EQ(0, std::memcmp(a->bgr.data(), b->bgr.data(), 640 * 480 * 3));
  // 5 cm further on, the image has changed.
  CameraRenderer(s, 1).render({0.05, 0, 0}, *c);
  EXPECT_NE(0, std::memcmp(a->bgr.data(), c->bgr.data(), 640 * 480 * 3));
}

// The renderer exposes the colours it draws instead of every pixel after: the frame must equal
// the unexposed frame put through CameraEffects::apply (exposure per pixel, then glare).
TEST(CameraRendererTest, ExposureInTheColoursEqualsExposingTheFrame) {
  for (const double exposure : {0.6, 1.3, 2.5}) {
    Scenario s = dot_scenario(1.1, 0.05);
    s.lines[0].points = {{0.5, -0.2}, {1.5, 0.3}};
    s.glare.intensity = 80.0;
    s.glare.radius_px = 40.0;
    Scenario plain = s;
    plain.glare.intensity = 0.0;
    s.robot.camera.exposure = exposure;
    auto drawn = std::make_unique<hal::CameraFrame>(), after = std::make_unique<hal::CameraFrame>();
    const Pose2 pose{0.1, 0.0, 0.2};
    CameraRenderer(s, 5).render(pose, *drawn);
    CameraRenderer(plain, 5).render(pose, *after);
    CameraEffects(s, 5).apply(*after, 0);
    EXPECT_EQ(0, std::memcmp(drawn->bgr.data(), after->bgr.data(), 640 * 480 * 3)) << exposure;
  }
}

// Noise is added with saturation: a bright floor never wraps round to dark, nor a dark one to
// bright (the noise loop works in 16 bits over runs of the sample table).
TEST(CameraRendererTest, NoiseSaturatesInsteadOfWrapping) {
  for (const int level : {3, 252}) {
    Scenario s = dot_scenario(-5.0, 0.0);
    s.floor = {std::uint8_t(level), std::uint8_t(level), std::uint8_t(level)};
    s.floor_speckle = 0.0;
    s.robot.camera.noise_std = 20.0;
    auto f = std::make_unique<hal::CameraFrame>();
    CameraRenderer r(s, 11);
    int far = 0, changed = 0;
    for (int k = 0; k < 3; ++k) {
      r.render({0, 0, 0}, *f);
      for (std::size_t i = 0; i < 640 * 480 * 3; ++i) {
        far += std::abs(int(f->bgr[i]) - level) > 128;
        changed += f->bgr[i] != level;
      }
    }
    EXPECT_EQ(far, 0) << level;
    EXPECT_GT(changed, 3 * 640 * 480) << level;  // about half of them move away from the bound
  }
}

// A scenario file of the repository, loaded as a run would.
Scenario repo_scenario(const char* name) {
  LoadResult r =
      load_scenario(std::string(CARRIL_SOURCE_DIR) + "/scenarios/" + name, test::robots_dir());
  EXPECT_TRUE(r.ok) << r.error;
  return r.scenario;
}

// A robot pose near the scenario's tape, marks or obstacles (or anywhere near the course), at any
// heading: most frames show tape, speckles and shapes cut by the image border.
Pose2 random_pose(const Scenario& s, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double pick = u(rng);
  Vec2 c{0.0, 0.0};
  if (pick < 0.6 && !s.lines.empty()) {
    const auto& pts = s.lines[std::size_t(u(rng) * double(s.lines.size()))].points;
    const std::size_t k = std::size_t(u(rng) * double(pts.size() - 1));
    const Vec2 a = pts[k], b = pts[std::min(k + 1, pts.size() - 1)];
    const double t = u(rng);
    c = {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t};
  } else if (pick < 0.75 && !s.marks.empty()) {
    c = s.marks[std::size_t(u(rng) * double(s.marks.size()))].center;
  } else if (pick < 0.9 && !s.obstacles.empty()) {
    c = s.obstacles[std::size_t(u(rng) * double(s.obstacles.size()))].center;
  } else {
    c = {-30.0 + 60.0 * u(rng), -30.0 + 60.0 * u(rng)};
  }
  return {c.x + 3.0 * (u(rng) - 0.5), c.y + 3.0 * (u(rng) - 0.5), 2.0 * M_PI * (u(rng) - 0.5)};
}

// The fast paths (floor fill, culled texture walk) write exactly the bytes of the plain ones:
// random poses over the repository's courses with worn tape, speckle, exposure, glare, noise
// and camera mounts from steep to above the horizon, a sequence of frames per renderer pair.
TEST(CameraRendererTest, FastPathsEqualReferenceByteForByte) {
  struct Case {
    const char* file;
    double speckle, exposure, glare, noise, fade, gaps, tilt_deg, hfov_deg, z_m, y_m;
    int width, height;
  };
  const Case cases[] = {
      {"square.yaml", -1, 1.0, 0, 0, 0, 0, -1, -1, -1, 0, 640, 480},
      {"circle.yaml", 0.15, 1.1, 40, 0, 0.1, 0.05, -1, -1, -1, 0, 640, 480},
      {"corners.yaml", 0.2, 0.9, 60, 4, 0.25, 0.1, -1, -1, -1, 0, 640, 480},
      {"smooth_red.yaml", 0.1, 1.2, 20, 2, 0.2, 0.08, -1, -1, -1, 0, 640, 480},
      {"corners_red.yaml", 0.3, 0.85, 0, 0, 0, 0, 12, 70, 0.3, 0.05, 640, 480},
      {"smooth.yaml", 0.0, 1.0, 30, 0, 0, 0, 88, 60, 0.8, -0.1, 640, 480},
      {"taxi_city.yaml", 0.18, 1.05, 0, 0, 0.1, 0.2, 30, 100, 0.2, 0, 320, 240},
      {"corridor_blocked.yaml", 0.12, 1.0, 50, 0, 0, 0, 5, 50, 1.2, 0, 640, 480},
      // A frame whose bytes are not a whole number of the floor fill's 192-byte blocks.
      {"square.yaml", 0.1, 1.0, 0, 0, 0, 0, -1, -1, -1, 0, 161, 121},
  };
  std::mt19937_64 rng(2024);
  auto fast = std::make_unique<hal::CameraFrame>(), ref = std::make_unique<hal::CameraFrame>();
  // A third renderer draws every frame over its own last one (as_rendered): only what that one
  // drew is put back to floor first.
  auto over = std::make_unique<hal::CameraFrame>();
  int frames = 0, unfilled = 0;
  for (const Case& c : cases) {
    Scenario s = repo_scenario(c.file);
    if (c.speckle >= 0) s.floor_speckle = c.speckle;
    CameraSpec& cam = s.robot.camera;
    cam.exposure = c.exposure;
    cam.noise_std = c.noise;
    s.glare.intensity = c.glare;
    s.tape_wear.fade = c.fade;
    s.tape_wear.gaps_per_m = c.gaps;
    if (c.tilt_deg > 0) cam.tilt_deg = c.tilt_deg;
    if (c.hfov_deg > 0) cam.hfov_deg = c.hfov_deg;
    if (c.z_m > 0) cam.z_m = c.z_m;
    cam.y_m += c.y_m;
    cam.width = c.width;
    cam.height = c.height;
    CameraRenderer a(s, 3), b(s, 3), d(s, 3);
    b.use_reference_path(true);
    const std::uint64_t unfills_before = d.unfills();
    for (int k = 0; k < 150; ++k) {
      const Pose2 pose = random_pose(s, rng);
      a.render(pose, *fast);
      b.render(pose, *ref);
      d.render(pose, *over, true);
      const std::size_t bytes = std::size_t(c.width) * std::size_t(c.height) * 3;
      ASSERT_EQ(0, std::memcmp(fast->bgr.data(), ref->bgr.data(), bytes))
          << c.file << " frame " << k << " pose " << pose.x << " " << pose.y << " " << pose.yaw_rad;
      ASSERT_EQ(0, std::memcmp(over->bgr.data(), ref->bgr.data(), bytes))
          << c.file << " frame " << k << " drawn over the last";
      ++frames;
    }
    // Every frame after the first is drawn over its predecessor, unless noise touched every pixel.
    EXPECT_EQ(d.unfills() - unfills_before, c.noise > 0 ? 0U : 149U) << c.file;
    unfilled += int(d.unfills() - unfills_before);
  }
  EXPECT_EQ(frames, 9 * 150);
  EXPECT_EQ(unfilled, 7 * 149);
}

// A frame drawn over is only trusted when the caller vouches for it: a buffer written to since
// (here, painted white) and not vouched for is filled whole, and equals a fresh render.
TEST(CameraRendererTest, AFrameNotVouchedForIsFilledWhole) {
  Scenario s = repo_scenario("circle.yaml");
  s.glare.intensity = 40;
  CameraRenderer a(s, 5), b(s, 5);
  auto over = std::make_unique<hal::CameraFrame>(), fresh = std::make_unique<hal::CameraFrame>();
  const std::size_t bytes = std::size_t(s.robot.camera.width) * s.robot.camera.height * 3;
  std::mt19937_64 rng(7);
  for (int k = 0; k < 40; ++k) {
    const Pose2 pose = random_pose(s, rng);
    const bool tampered = k % 5 == 4;
    if (tampered) std::memset(over->bgr.data(), 255, bytes);
    a.render(pose, *over, !tampered);
    b.render(pose, *fresh);
    ASSERT_EQ(0, std::memcmp(over->bgr.data(), fresh->bgr.data(), bytes)) << "frame " << k;
  }
  EXPECT_EQ(a.unfills(), 39U - 8U);  // all but the first and the 8 tampered ones
  // Vouching for a tampered buffer is the caller's error, and shows: the paint stays.
  std::memset(over->bgr.data(), 255, bytes);
  const Pose2 pose = random_pose(s, rng);
  a.render(pose, *over, true);
  b.render(pose, *fresh);
  EXPECT_NE(0, std::memcmp(over->bgr.data(), fresh->bgr.data(), bytes));
}

}  // namespace
}  // namespace carril::sim
