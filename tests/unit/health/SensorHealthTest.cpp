// The sensor health rules, fed sample by sample: each fires when its sensor goes blind or stuck,
// within its documented window, and not on a working sensor (each fault case has a control).
#include "firmware/health/SensorHealth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

namespace carril::fw {
namespace {

// ---- Lidar ----

hal::LaserScan scan_filled(float r, int count = 360) {
  hal::LaserScan s;
  s.count = std::uint16_t(count);
  s.range_min_m = 0.05F;
  s.range_max_m = 8.0F;
  for (int i = 0; i < count; ++i) s.ranges_m[std::size_t(i)] = r;
  return s;
}

class ScanHealthBlind : public testing::TestWithParam<float> {};

TEST_P(ScanHealthBlind, FaultsOnTheScanThatFillsTheWindow) {
  ScanHealthConfig cfg;
  ScanHealth h(cfg);
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(h.add(scan_filled(2.0F)));
  EXPECT_DOUBLE_EQ(h.valid_fraction(), 1.0);
  // Blind from here: the window still holds good scans for a while.
  int blind = 0;
  while (h.add(scan_filled(GetParam()))) {
    ++blind;
    ASSERT_LT(blind, cfg.window_scans) << "not declared blind within the window";
  }
  // 5 scans: at 95% of the window blind, i.e. the 5th blind scan.
  EXPECT_EQ(blind + 1, cfg.window_scans);
  EXPECT_LT(h.valid_fraction(), cfg.min_valid_fraction);
}

INSTANTIATE_TEST_SUITE_P(Ranges, ScanHealthBlind,
                         testing::Values(std::numeric_limits<float>::quiet_NaN(), 0.0F, -1.0F, 9.0F,
                                         0.01F));

TEST(ScanHealthTest, BlindFromTheFirstScan) {
  ScanHealth h(ScanHealthConfig{});
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(h.add(scan_filled(0.0F))) << i;  // window not full
  EXPECT_FALSE(h.add(scan_filled(0.0F)));
}

TEST(ScanHealthTest, OpenViewIsHealthy) {
  // Control: a short-range scanner in a large hall sees nothing within range (+inf) on most or
  // all of its beams; something right against it reads -inf. Both are measurements.
  ScanHealth h(ScanHealthConfig{});
  hal::LaserScan s = scan_filled(std::numeric_limits<float>::infinity());
  for (int i = 0; i < 50; ++i) ASSERT_TRUE(h.add(s));
  for (int i = 0; i < 36; ++i) s.ranges_m[std::size_t(i)] = -std::numeric_limits<float>::infinity();
  for (int i = 0; i < 50; ++i) ASSERT_TRUE(h.add(s));
  EXPECT_DOUBLE_EQ(h.valid_fraction(), 1.0);
}

TEST(ScanHealthTest, MostlyGarbageWithAFewReturnsIsHealthy) {
  // 10% real returns among NaNs: a scanner with a dirty window, still seeing.
  ScanHealth h(ScanHealthConfig{});
  hal::LaserScan s = scan_filled(std::numeric_limits<float>::quiet_NaN());
  for (int i = 0; i < 36; ++i) s.ranges_m[std::size_t(i)] = 6.0F;
  for (int i = 0; i < 50; ++i) ASSERT_TRUE(h.add(s));
  EXPECT_NEAR(h.valid_fraction(), 0.1, 1e-9);
}

TEST(ScanHealthTest, OneBadScanAmongGoodOnesIsHealthy) {
  ScanHealth h(ScanHealthConfig{});
  for (int i = 0; i < 50; ++i) {
    ASSERT_TRUE(h.add(scan_filled(i % 5 == 0 ? std::numeric_limits<float>::quiet_NaN() : 3.0F)));
  }
}

TEST(ScanHealthTest, ScanWithNoBeamsIsNotValid) {
  ScanHealth h(ScanHealthConfig{});
  bool ok = true;
  for (int i = 0; i < 5; ++i) ok = h.add(scan_filled(2.0F, 0));
  EXPECT_FALSE(ok);
}

// ---- Camera ----

// A 160x120 frame (or `width` wide): floor grey with a speckle pattern that shifts with
// `offset` px.
std::unique_ptr<hal::CameraFrame> textured(int offset, int width = 160) {
  auto f = std::make_unique<hal::CameraFrame>();
  f->width = std::uint16_t(width);
  f->height = 120;
  for (int v = 0; v < 120; ++v) {
    for (int u = 0; u < width; ++u) {
      const bool speck = ((u + offset) / 7 + v / 5) % 3 == 0;
      for (int c = 0; c < 3; ++c) f->pixel(u, v)[c] = speck ? 100 : 90;
    }
  }
  return f;
}

std::unique_ptr<hal::CameraFrame> flat(std::uint8_t b, std::uint8_t g, std::uint8_t r) {
  auto f = std::make_unique<hal::CameraFrame>();
  f->width = 160;
  f->height = 120;
  for (int v = 0; v < 120; ++v) {
    for (int u = 0; u < 160; ++u) {
      f->pixel(u, v)[0] = b;
      f->pixel(u, v)[1] = g;
      f->pixel(u, v)[2] = r;
    }
  }
  return f;
}

TEST(FrameHealthTest, FlatFramesAreBlankAfterTheConfiguredRun) {
  FrameHealthConfig cfg;
  FrameHealth h(cfg);
  const auto black = flat(0, 0, 0);
  Pose2 p;
  for (int i = 1; i < cfg.blank_frames; ++i) {
    p.x += 0.001;  // crawling: the frozen rule stays out of it
    EXPECT_EQ(h.add(*black, p), FrameVerdict::Ok) << i;
  }
  EXPECT_EQ(h.add(*black, p), FrameVerdict::Blank);
  EXPECT_EQ(h.last_spread(), 0);
}

TEST(FrameHealthTest, AnyFlatColourIsBlankAndAGoodFrameResetsTheRun) {
  FrameHealthConfig cfg;
  FrameHealth h(cfg);
  const auto green = flat(0, 255, 0);
  const auto good = textured(0);
  const Pose2 still;
  for (int i = 1; i < cfg.blank_frames; ++i) EXPECT_EQ(h.add(*green, still), FrameVerdict::Ok);
  EXPECT_EQ(h.add(*good, still), FrameVerdict::Ok);  // the run starts again
  for (int i = 1; i < cfg.blank_frames; ++i) EXPECT_EQ(h.add(*green, still), FrameVerdict::Ok);
  EXPECT_EQ(h.add(*green, still), FrameVerdict::Blank);
}

TEST(FrameHealthTest, FlatFramesWhileDrivingAreBlankNotFrozen) {
  FrameHealthConfig cfg;
  FrameHealth h(cfg);
  const auto black = flat(0, 0, 0);
  Pose2 p;
  FrameVerdict v = FrameVerdict::Ok;
  for (int i = 0; i < cfg.blank_frames && v == FrameVerdict::Ok; ++i) {
    v = h.add(*black, p);
    p.x += 0.03;
  }
  EXPECT_EQ(v, FrameVerdict::Blank);
}

TEST(FrameHealthTest, TexturedFloorIsNotBlank) {
  FrameHealth h(FrameHealthConfig{});
  const auto f = textured(0);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(h.add(*f, Pose2{}), FrameVerdict::Ok);
  EXPECT_EQ(h.last_spread(), 10);
}

TEST(FrameHealthTest, SameImageWhileStandingStillIsFine) {
  FrameHealth h(FrameHealthConfig{});
  const auto f = textured(3);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(h.add(*f, Pose2{1.0, 2.0, 0.3}), FrameVerdict::Ok);
}

TEST(FrameHealthTest, SameImageWhileDrivingIsFrozen) {
  FrameHealthConfig cfg;
  FrameHealth h(cfg);
  const auto f = textured(3);
  Pose2 p;
  FrameVerdict v = FrameVerdict::Ok;
  int frames = 0;
  while (v == FrameVerdict::Ok && frames < 100) {
    v = h.add(*f, p);
    p.x += 0.0167;  // 0.5 m/s at 30 Hz
    ++frames;
  }
  EXPECT_EQ(v, FrameVerdict::Frozen);
  // The image may not stay the same over more than frozen_motion_m of travel.
  EXPECT_LE((frames - 1) * 0.0167, cfg.frozen_motion_m + 0.0167);
}

TEST(FrameHealthTest, SameImageWhileTurningIsFrozen) {
  FrameHealth h(FrameHealthConfig{});
  const auto f = textured(3);
  Pose2 p;
  FrameVerdict v = FrameVerdict::Ok;
  for (int i = 0; i < 10 && v == FrameVerdict::Ok; ++i) {
    v = h.add(*f, p);
    p.yaw += 0.02;
  }
  EXPECT_EQ(v, FrameVerdict::Frozen);
}

TEST(FrameHealthTest, ChangingImageWhileDrivingIsFine) {
  // Control for the two above: the same motion with an image that moves with it.
  FrameHealth h(FrameHealthConfig{});
  Pose2 p;
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(h.add(*textured(i), p), FrameVerdict::Ok) << i;
    p.x += 0.0167;
    p.yaw += 0.02;
  }
}

TEST(FrameHealthTest, OneSampledPixelChangingIsAChangedImage) {
  // Every sample counts, in each of the hash's four lanes (samples taken four at a time along a
  // row) and in the row's tail past the last group of four, in each channel, in the first and
  // the last sampled row: the frozen rule must not fire while any of them moves. And the spread
  // sees that sample as well. 160 px: 20 samples a row, no tail; 150 px: 19, a tail of 3.
  const FrameHealthConfig cfg;
  const int step = cfg.sample_step_px, half = step / 2;
  const int last_v = half + ((120 - 1 - half) / step) * step;
  for (const int width : {160, 150}) {
    const int last_u = half + ((width - 1 - half) / step) * step;
    const int us[] = {half, half + step, half + 2 * step, half + 3 * step, last_u - step, last_u};
    for (const int v : {half, last_v}) {
      for (const int u : us) {
        for (int c = 0; c < 3; ++c) {
          FrameHealth h(cfg);
          auto f = textured(3, width);
          Pose2 p;
          for (int i = 0; i < 20; ++i) {
            f->pixel(u, v)[c] = std::uint8_t(i % 2 == 0 ? 90 : 91);
            EXPECT_EQ(h.add(*f, p), FrameVerdict::Ok)
                << "width " << width << " u " << u << " v " << v << " channel " << c << " " << i;
            p.x += 0.0167;
          }
          FrameHealth s(cfg);
          f->pixel(u, v)[c] = 250;  // far above the texture's 90 to 100
          s.add(*f, Pose2{});
          EXPECT_EQ(s.last_spread(), 250 - 90) << "width " << width << " u " << u << " v " << v;
          f->pixel(u, v)[c] = 20;  // and far below
          s.add(*f, Pose2{});
          EXPECT_EQ(s.last_spread(), 100 - 20) << "width " << width << " u " << u << " v " << v;
        }
      }
    }
  }
}

// ---- IMU ----

hal::ImuSample imu(double t_s, float wz, float roll = 0.0F) {
  hal::ImuSample s;
  s.valid = true;
  s.stamp_ns = hal::TimeNs(t_s * 1e9);
  s.yaw_rate_radps = wz;
  s.roll_rad = roll;
  return s;
}

TEST(ImuHealthTest, LiveSamplesAreFine) {
  ImuHealth h(ImuHealthConfig{});
  for (int i = 0; i < 300; ++i) {
    const double t = i * 0.01;
    const float wz = float(0.5 * std::sin(t));
    EXPECT_EQ(h.add(imu(t, wz), t, double(wz)), ImuVerdict::Ok) << i;
  }
}

TEST(ImuHealthTest, SameValuesWhileDrivingStraightAreFine) {
  // The simulator's noise-free IMU on a straight: roll, pitch and yaw rate all exactly zero.
  ImuHealth h(ImuHealthConfig{});
  for (int i = 0; i < 300; ++i)
    EXPECT_EQ(h.add(imu(i * 0.01, 0.0F), i * 0.01, 0.0), ImuVerdict::Ok);
}

TEST(ImuHealthTest, SameStampForTooLongIsFrozen) {
  ImuHealthConfig cfg;
  ImuHealth h(cfg);
  const hal::ImuSample s = imu(0.0, 0.1F);
  ImuVerdict v = ImuVerdict::Ok;
  double t = 0.0;
  while (v == ImuVerdict::Ok && t < 5.0) {
    t += 0.01;
    v = h.add(s, t, 0.1);
  }
  EXPECT_EQ(v, ImuVerdict::Frozen);
  EXPECT_NEAR(t, cfg.frozen_s, 0.02);
}

TEST(ImuHealthTest, SameValuesWhileTheOdometryTurnsIsFrozen) {
  ImuHealthConfig cfg;
  ImuHealth h(cfg);
  ImuVerdict v = ImuVerdict::Ok;
  double t = 0.0;
  while (v == ImuVerdict::Ok && t < 5.0) {
    t += 0.01;
    v = h.add(imu(t, 0.0F), t, 0.5 * t);  // fresh stamps, stuck yaw rate; the robot turns faster
  }
  EXPECT_EQ(v, ImuVerdict::Frozen);
  EXPECT_NEAR(t, cfg.frozen_s, 0.02);
}

TEST(ImuHealthTest, ImplausibleValuesAreOutOfRangeAfterTheConfiguredRun) {
  ImuHealthConfig cfg;
  for (const hal::ImuSample bad :
       {imu(0, 0.0F, std::numeric_limits<float>::quiet_NaN()), imu(0, 100.0F), imu(0, 0.0F, 1.0F),
        imu(0, std::numeric_limits<float>::infinity())}) {
    ImuHealth h(cfg);
    for (int i = 1; i < cfg.out_of_range_samples; ++i) {
      hal::ImuSample s = bad;
      s.stamp_ns = i;
      EXPECT_EQ(h.add(s, i * 0.01, 0.0), ImuVerdict::Ok);
    }
    EXPECT_EQ(h.add(bad, 1.0, 0.0), ImuVerdict::OutOfRange);
  }
}

TEST(ImuHealthTest, NoSampleIsNothingToJudge) {
  ImuHealth h(ImuHealthConfig{});
  for (int i = 0; i < 300; ++i)
    EXPECT_EQ(h.add(hal::ImuSample{}, i * 0.01, 0.3 * i), ImuVerdict::Ok);
}

}  // namespace
}  // namespace carril::fw
