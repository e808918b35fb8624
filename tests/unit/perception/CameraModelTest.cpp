#include "firmware/perception/CameraModel.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace carril::fw {
namespace {

constexpr double kDeg = kPi / 180.0;

// Camera 1 m above the floor, 0.5 m ahead of the robot centre, looking 45 deg down; 90 deg
// horizontal field of view on a 640x480 image.
CameraMount mount45() {
  CameraMount m;
  m.x_m = 0.5;
  m.y_m = 0.0;
  m.z_m = 1.0;
  m.tilt_rad = 45 * kDeg;
  m.hfov_rad = 90 * kDeg;
  m.width = 640;
  m.height = 480;
  return m;
}

TEST(CameraModelTest, Intrinsics) {
  const CameraModel cam(mount45());
  EXPECT_NEAR(cam.fx(), 320.0, 1e-9);  // (640 / 2) / tan(45 deg)
  EXPECT_DOUBLE_EQ(cam.cx(), 319.5);   // (640 - 1) / 2: pixel centres at integers
  EXPECT_DOUBLE_EQ(cam.cy(), 239.5);
}

TEST(CameraModelTest, OpticalAxisHitsImageCentre) {
  const CameraModel cam(mount45());
  // The axis leaves (0.5, 0, 1) at 45 deg down and reaches the floor 1 m further ahead.
  Vec2 px;
  ASSERT_TRUE(cam.floor_to_pixel(Vec2(1.5, 0.0), px));
  EXPECT_NEAR(px.x(), 319.5, 1e-9);
  EXPECT_NEAR(px.y(), 239.5, 1e-9);
  Vec2 back;
  ASSERT_TRUE(cam.pixel_to_floor(Vec2(319.5, 239.5), back));
  EXPECT_NEAR(back.x(), 1.5, 1e-9);
  EXPECT_NEAR(back.y(), 0.0, 1e-9);
}

TEST(CameraModelTest, OffAxisPixelByHand) {
  const CameraModel cam(mount45());
  // Floor point P = (2.5, -0.5, 0), camera centre C = (0.5, 0, 1): d = P - C = (2, -0.5, -1).
  // Camera axes in the robot frame, with c = s = sqrt(2)/2 for 45 deg:
  //   x (image right) = (0, -1, 0)   -> xc = 0.5
  //   y (image down)  = (-s, 0, -c)  -> yc = -2s + c = -sqrt(2)/2
  //   z (optical)     = (c, 0, -s)   -> zc = 2c + s = 3 sqrt(2)/2
  // Pinhole: u = f xc / zc + cx = 320 * 0.5 / (3 sqrt(2)/2) + 319.5 = 320 / (3 sqrt(2)) + 319.5
  //            = 75.42472... + 319.5 = 394.92472...
  //          v = f yc / zc + cy = 320 * (-1/3) + 239.5 = 132.83333...
  const double u = 320.0 / (3.0 * std::sqrt(2.0)) + 319.5;
  const double v = -320.0 / 3.0 + 239.5;
  EXPECT_NEAR(u, 394.924723, 1e-6);
  Vec2 px;
  ASSERT_TRUE(cam.floor_to_pixel(Vec2(2.5, -0.5), px));
  EXPECT_NEAR(px.x(), u, 1e-9);
  EXPECT_NEAR(px.y(), v, 1e-9);
  ASSERT_TRUE(cam.project(Vec3(2.5, -0.5, 0.0), px));
  EXPECT_NEAR(px.x(), u, 1e-9);
  EXPECT_NEAR(px.y(), v, 1e-9);
}

TEST(CameraModelTest, SidewaysPointOnCentreRow) {
  const CameraModel cam(mount45());
  // P = (1.5, 0.5, 0): d = (1, 0.5, -1); xc = -0.5, yc = -s + c = 0, zc = c + s = sqrt(2).
  // u = 320 * -0.5 / sqrt(2) + 319.5 = 319.5 - 113.137...; v = cy.
  Vec2 px;
  ASSERT_TRUE(cam.floor_to_pixel(Vec2(1.5, 0.5), px));
  EXPECT_NEAR(px.x(), 319.5 - 160.0 / std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(px.y(), 239.5, 1e-9);
}

TEST(CameraModelTest, ImageDirections) {
  const CameraModel cam(mount45());
  Vec2 centre, left, right, far, near;
  ASSERT_TRUE(cam.floor_to_pixel(Vec2(1.5, 0.0), centre));
  ASSERT_TRUE(cam.floor_to_pixel(Vec2(1.5, 0.2), left));  // y > 0 is the robot's left
  ASSERT_TRUE(cam.floor_to_pixel(Vec2(1.5, -0.2), right));
  ASSERT_TRUE(cam.floor_to_pixel(Vec2(2.0, 0.0), far));
  ASSERT_TRUE(cam.floor_to_pixel(Vec2(1.2, 0.0), near));
  EXPECT_LT(left.x(), centre.x());
  EXPECT_GT(right.x(), centre.x());
  EXPECT_LT(far.y(), centre.y());  // farther is higher in the image
  EXPECT_GT(near.y(), centre.y());
  EXPECT_NEAR(far.x(), centre.x(), 1e-9);  // straight ahead stays on the centre column
}

TEST(CameraModelTest, FloorRoundTrip) {
  const CameraModel cam(mount45());
  const Vec2 pts[] = {{1.5, 0.0}, {1.0, 0.3}, {2.7, -0.9}, {0.9, -0.1}, {4.0, 1.5}};
  for (const Vec2& p : pts) {
    Vec2 px, back;
    ASSERT_TRUE(cam.floor_to_pixel(p, px)) << p.transpose();
    ASSERT_TRUE(cam.pixel_to_floor(px, back)) << p.transpose();
    EXPECT_NEAR(back.x(), p.x(), 1e-9) << p.transpose();
    EXPECT_NEAR(back.y(), p.y(), 1e-9) << p.transpose();
  }
}

TEST(CameraModelTest, ProjectAgreesWithHomographyOnFloor) {
  CameraMount m = mount45();
  m.y_m = 0.07;  // off-centre mount, odd tilt: exercise every term
  m.tilt_rad = 33 * kDeg;
  const CameraModel cam(m);
  const Vec2 pts[] = {{1.0, 0.0}, {2.0, 0.5}, {3.0, -1.0}, {1.4, 0.9}};
  for (const Vec2& p : pts) {
    Vec2 a, b;
    ASSERT_TRUE(cam.floor_to_pixel(p, a));
    ASSERT_TRUE(cam.project(Vec3(p.x(), p.y(), 0.0), b));
    EXPECT_NEAR(a.x(), b.x(), 1e-9);
    EXPECT_NEAR(a.y(), b.y(), 1e-9);
  }
}

TEST(CameraModelTest, ToCameraFrame) {
  const CameraModel cam(mount45());
  // A point 1 m along the optical axis from the centre: (0.5 + c, 0, 1 - s).
  const double c = std::sqrt(0.5);
  const Vec3 pc = cam.to_camera(Vec3(0.5 + c, 0.0, 1.0 - c));
  EXPECT_NEAR(pc.x(), 0.0, 1e-12);
  EXPECT_NEAR(pc.y(), 0.0, 1e-12);
  EXPECT_NEAR(pc.z(), 1.0, 1e-12);
  // A point to the robot's left is on the camera's -x.
  EXPECT_NEAR(cam.to_camera(Vec3(0.5, 1.0, 1.0)).x(), -1.0, 1e-12);
}

TEST(CameraModelTest, PointBehindCameraRejected) {
  const CameraModel cam(mount45());
  Vec2 px;
  // Level with the camera, behind it.
  EXPECT_FALSE(cam.project(Vec3(0.0, 0.0, 1.0), px));
  // Depth of a floor point is (x - 0.5) c + s: negative for x < -0.5.
  EXPECT_FALSE(cam.floor_to_pixel(Vec2(-1.0, 0.0), px));
  EXPECT_FALSE(cam.project(Vec3(-1.0, 0.0, 0.0), px));
  // The floor just below the camera is in front of the image plane (depth s > 0).
  EXPECT_TRUE(cam.floor_to_pixel(Vec2(0.5, 0.0), px));
}

TEST(CameraModelTest, PixelAboveHorizonDoesNotHitFloor) {
  CameraMount m = mount45();
  m.tilt_rad = 10 * kDeg;
  const CameraModel cam(m);
  // Half the vertical field of view is atan(239.5 / 320) = 36.8 deg > 10 deg tilt: the top
  // row looks 26.8 deg above the horizon.
  Vec2 floor;
  EXPECT_FALSE(cam.pixel_to_floor(Vec2(319.5, 0.0), floor));
  EXPECT_FALSE(cam.pixel_to_floor(Vec2(0.0, 0.0), floor));
  // Horizon row: v = cy - f tan(10 deg) = 239.5 - 56.42 = 183.08. Rows just below it hit the
  // floor far away; the bottom row hits it close.
  const double horizon_v = 239.5 - 320.0 * std::tan(10 * kDeg);
  EXPECT_FALSE(cam.pixel_to_floor(Vec2(319.5, horizon_v - 1.0), floor));
  ASSERT_TRUE(cam.pixel_to_floor(Vec2(319.5, horizon_v + 1.0), floor));
  EXPECT_GT(floor.x(), 10.0);
  ASSERT_TRUE(cam.pixel_to_floor(Vec2(319.5, 479.0), floor));
  // Bottom row looks 10 + 36.8 deg down from 1 m: hits the floor about 0.94 m ahead.
  const double down = 10 * kDeg + std::atan(239.5 / 320.0);
  EXPECT_NEAR(floor.x(), 0.5 + 1.0 / std::tan(down), 1e-9);
  EXPECT_NEAR(floor.y(), 0.0, 1e-9);
}

}  // namespace
}  // namespace carril::fw
