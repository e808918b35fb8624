// Static allocation, proven without the simulator, so it runs wherever the firmware runs (the
// aarch64 cross build under qemu included): this binary replaces the global allocators with
// counting versions (host_sim/alloc/AllocCounter), wires fw::Firmware and FirmwareApp to
// fake HAL devices (the in-process hal/sim backends, fed here: camera frames with a tape line
// drawn in, empty-room scans, IMU samples, wheel feedback from ideal motors) and runs hundreds of
// ticks after init. Not one allocation may happen inside a tick.
#include <gtest/gtest.h>

#include <malloc.h>
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "firmware/app/Firmware.hpp"
#include "firmware/app/FirmwareApp.hpp"
#include "firmware/app/FirmwareConfig.hpp"
#include "firmware/core/Faults.hpp"
#include "hal/Devices.hpp"
#include "hal/sim/SimDevices.hpp"
#include "host_sim/alloc/AllocCounter.hpp"

#include "firmware/core/Geometry.hpp"

namespace carril::fw {
namespace {

constexpr double kTapeHalfWidthM = 0.025;  // 5 cm tape along the robot's heading

// Keeps the compiler from eliding an allocation/free pair (allowed since C++14).
void escape(void* p) {
  asm volatile("" : : "g"(p) : "memory");
}

FirmwareConfig white_tape_config() {
  FirmwareConfig c;  // a differential robot with camera, lidar and IMU (the defaults)
  EXPECT_TRUE(color_preset("white", c.camera.detector.line));
  EXPECT_TRUE(color_preset("yellow", c.camera.detector.end));
  apply_sensor_rates(c);
  const Status st = c.validate();
  EXPECT_TRUE(st) << st.message();
  return c;
}

// The firmware on fake devices, and the world those devices report: a straight white tape
// ahead on a grey floor, nothing within lidar range, wheels that turn as commanded.
class FakeRobot {
 public:
  FakeRobot()
      : config_(white_tape_config()),
        drives_(DriveKinematics(config_.drive).wheel_count()),
        devices_{clock_, drives_, camera_, scanner_, imu_},
        firmware_(std::make_unique<Firmware>(config_, clock_)),  // large: on the heap
        app_(devices_, firmware_->controller),
        period_ns_(std::llround(1e9 / config_.rate_hz)),
        cam_period_ns_(std::llround(1e9 / config_.camera.rate_hz)),
        scan_period_ns_(std::llround(1e9 / config_.lidar.rate_hz)) {
    const Status st = firmware_->declare_tasks();  // both targets' table
    EXPECT_TRUE(st) << st.message();
    draw_tape_mask();
  }

  // One control period: the devices publish, the firmware ticks inside a counting window, the
  // motors follow what was synced.
  void step() {
    const hal::TimeNs t = hal::TimeNs(tick_) * period_ns_;
    clock_.set_now_ns(t);
    publish_sensors(t);

    Eigen::internal::set_is_malloc_allowed(false);
    alloc::begin_window();
    app_.step();
    alloc::end_window();
    Eigen::internal::set_is_malloc_allowed(true);

    drives_.take_setpoints(wheel_radps_);
    const double dt = 1.0 / config_.rate_hz;
    for (int i = 0; i < drives_.count(); ++i) wheel_rad_[i] += double(wheel_radps_[i]) * dt;
    ++tick_;
  }

  Firmware& firmware() { return *firmware_; }
  hal::SimWheelDrives& drives() { return drives_; }
  std::uint64_t frames_published() const { return frames_; }

 private:
  // Which pixels see the tape: the camera model's own floor mapping, once at init.
  void draw_tape_mask() {
    const CameraModel& cam = firmware_->perception.camera();
    const int w = cam.mount().width, h = cam.mount().height;
    tape_.assign(std::size_t(w) * std::size_t(h), 0);
    for (int v = 0; v < h; ++v) {
      for (int u = 0; u < w; ++u) {
        Vec2 floor;
        if (cam.pixel_to_floor(Vec2(u + 0.5, v + 0.5), floor) &&
            std::fabs(floor.y()) < kTapeHalfWidthM) {
          tape_[std::size_t(v) * std::size_t(w) + std::size_t(u)] = 1;
        }
      }
    }
  }

  void publish_sensors(hal::TimeNs t) {
    if (t >= next_cam_ns_) {
      hal::CameraFrame& f = camera_.back_buffer();
      const CameraMount& m = firmware_->perception.camera().mount();
      f.width = std::uint16_t(m.width);
      f.height = std::uint16_t(m.height);
      // The floor's shade changes a little from frame to frame, as a real one does: an image that
      // stays identical while the robot moves is a frozen camera.
      const auto grey = std::uint8_t(96 + frames_ % 8);
      for (std::size_t i = 0; i < tape_.size(); ++i) {
        const std::uint8_t c = tape_[i] ? std::uint8_t(250) : grey;
        f.bgr[3 * i] = c;
        f.bgr[3 * i + 1] = c;
        f.bgr[3 * i + 2] = c;
      }
      camera_.publish(t);
      ++frames_;
      next_cam_ns_ += cam_period_ns_;
    }
    if (t >= next_scan_ns_) {
      hal::LaserScan& s = scanner_.back_buffer();
      s.count = 360;
      s.angle_min_rad = float(-kPi);
      s.angle_increment_rad = float(2.0 * kPi / 360.0);
      s.range_min_m = 0.05F;
      s.range_max_m = 10.0F;
      // An empty hall: no return within range on any beam (REP 117: +inf).
      for (int i = 0; i < s.count; ++i) s.ranges_m[i] = std::numeric_limits<float>::infinity();
      scanner_.publish(t);
      next_scan_ns_ += scan_period_ns_;
    }
    hal::ImuSample imu;
    imu.stamp_ns = t;
    imu.valid = true;
    imu.yaw_rate_radps = float(firmware_->kinematics.forward(wheel_radps_).wz);
    imu_.publish(imu);
    for (int i = 0; i < drives_.count(); ++i) {
      drives_.set_feedback(i, t, wheel_radps_[i], wheel_rad_[i]);
    }
  }

  FirmwareConfig config_;
  hal::SimClock clock_;
  hal::SimCamera camera_;
  hal::SimRangeScanner scanner_;
  hal::SimImu imu_;
  hal::SimWheelDrives drives_;
  hal::Devices devices_;
  std::unique_ptr<Firmware> firmware_;
  FirmwareApp app_;
  std::vector<std::uint8_t> tape_;
  hal::TimeNs period_ns_, cam_period_ns_, scan_period_ns_;
  hal::TimeNs next_cam_ns_ = 0, next_scan_ns_ = 0;
  std::uint64_t tick_ = 0, frames_ = 0;
  float wheel_radps_[hal::kMaxWheels] = {};
  double wheel_rad_[hal::kMaxWheels] = {};
};

TEST(FirmwareAllocationTest, CounterSeesAnAllocationInsideAWindow) {
  // Control: the counter is live, so the zeros below mean something.
  const std::uint64_t before = alloc::count_in_windows();
  alloc::begin_window();
  int* p = new int(3);
  escape(p);
  alloc::end_window();
  delete p;
  EXPECT_EQ(alloc::count_in_windows() - before, 1U);
  if (alloc::counts_malloc()) {
    alloc::begin_window();
    void* m = std::malloc(16);
    escape(m);
    alloc::end_window();
    std::free(m);
    EXPECT_EQ(alloc::count_in_windows() - before, 2U);
  }
}

TEST(FirmwareAllocationTest, EveryFormOfAllocationIsCounted) {
  // The counter is one implementation for the simulator and the tests: each form it replaces
  // counts once (the aligned and nothrow operator new; memalign, valloc and posix_memalign where
  // malloc's family is counted).
  const std::uint64_t before = alloc::count_in_windows();
  std::uint64_t expected = 0;
  alloc::begin_window();
  void* a = ::operator new(64, std::align_val_t(64));
  void* b = ::operator new(64, std::align_val_t(64), std::nothrow);
  void* c = ::operator new[](8, std::nothrow);
  alloc::end_window();
  expected += 3;
  escape(a);
  escape(b);
  escape(c);
  ::operator delete(a, std::align_val_t(64));
  ::operator delete(b, std::align_val_t(64));
  ::operator delete[](c);
  EXPECT_EQ(alloc::count_in_windows() - before, expected);
  if (alloc::counts_malloc()) {
    void* d = nullptr;
    alloc::begin_window();
    void* e = memalign(64, 64);
    void* f = valloc(64);
    const int rc = posix_memalign(&d, 64, 64);
    alloc::end_window();
    expected += 3;
    escape(e);
    escape(f);
    EXPECT_EQ(rc, 0);
    std::free(d);
    std::free(e);
    std::free(f);
    EXPECT_EQ(alloc::count_in_windows() - before, expected);
  }
}

TEST(FirmwareAllocationTest, FollowingTheTapeAllocatesNothingInsideTicks) {
  const std::uint64_t total_before = alloc::count_total();
  FakeRobot robot;                                // init: allocating here is allowed
  EXPECT_GT(alloc::count_total(), total_before);  // counting is on
  const std::uint64_t before = alloc::count_in_windows();
  constexpr int kTicks = 600;  // 6 s at 100 Hz: 180 frames, 120 scans
  for (int i = 0; i < kTicks; ++i) robot.step();

  // The ticks did the real work: the mission left START and follows the tape, moving.
  const Firmware& f = robot.firmware();
  EXPECT_EQ(f.controller.ticks(), std::uint64_t(kTicks));
  EXPECT_STREQ(fault_name(f.controller.fault()), "none");
  EXPECT_EQ(std::string(f.controller.state_name()), "FOLLOW");
  EXPECT_GE(f.perception.telemetry().frames_processed, 150U);
  EXPECT_GE(f.watch.telemetry().scans, 100U);
  EXPECT_TRUE(std::isgreater(f.telemetry().odom.x, 0.2)) << f.telemetry().odom.x;

  EXPECT_EQ(alloc::count_in_windows() - before, 0U);
}

TEST(FirmwareAllocationTest, DriveFaultAndQuickStopAllocateNothingEither) {
  FakeRobot robot;
  const std::uint64_t before = alloc::count_in_windows();
  for (int i = 0; i < 300; ++i) robot.step();
  robot.drives().inject_fault(0, hal::DriveFault::Overcurrent);
  for (int i = 0; i < 300; ++i) robot.step();

  const Firmware& f = robot.firmware();
  EXPECT_STREQ(fault_name(f.controller.fault()), "drive_fault");
  EXPECT_EQ(std::string(f.controller.state_name()), "FAULT");
  EXPECT_GT(robot.drives().quick_stop_requests(), 0);
  EXPECT_EQ(alloc::count_in_windows() - before, 0U);
}

}  // namespace
}  // namespace carril::fw
