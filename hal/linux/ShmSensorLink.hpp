#pragma once
// Camera frames and IMU samples over POSIX shared memory (shm_open + mmap; the object's name,
// e.g. "/carril_sensors", comes from the configuration): the simulator writes, the controller
// reads through hal::Camera and hal::Imu. Lock-free and sequence-numbered: each kind has a ring
// of slots, each slot a seqlock (a version that is odd while the writer fills it), and a header
// word with the sequence number of the newest committed one.
//
// Copies: the writer renders into the slot itself (camera_begin/camera_commit) or copies once
// into it (publish_camera); the reader copies once out, into the frame the firmware gets. A
// reader never waits: it retries a torn copy (the writer lapped it) at most kMaxTries times, then
// keeps its previous frame and counts the drop. When the writer stops, nothing is new: the
// reader keeps returning the last frame with the same seq (stamp), and the firmware's sensor
// timeouts turn that into faults.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "hal/Camera.hpp"
#include "hal/Imu.hpp"

namespace carril::hal {

constexpr int kShmCameraSlots = 3;
constexpr int kShmImuSlots = 4;

// The shared memory object's layout (documented in docs/hil.md). Both sides must be built from
// the same layout: the reader checks magic, version and size.
struct ShmSensorLayout {
  static constexpr std::uint32_t kMagic = 0x4C53'5243U;  // "CRSL" little-endian
  static constexpr std::uint32_t kVersion = 1;
  struct alignas(64) Header {
    std::uint32_t magic;
    std::uint32_t version;
    std::uint64_t size;                        // sizeof(ShmSensorLayout) [bytes]
    std::atomic<std::uint64_t> camera_latest;  // seq of the newest frame, 0 = none yet
    std::atomic<std::uint64_t> imu_latest;     // seq of the newest IMU sample, 0 = none yet
  };
  struct alignas(64) CameraSlot {
    std::atomic<std::uint32_t> version;  // odd while being written
    CameraFrame frame;                   // frame.seq = the link's sequence number
  };
  struct alignas(64) ImuSlot {
    std::atomic<std::uint32_t> version;
    std::uint64_t seq;
    ImuSample sample;
  };
  Header header;
  CameraSlot camera[kShmCameraSlots];  // frame seq s lives in slot s % kShmCameraSlots
  ImuSlot imu[kShmImuSlots];
};
static_assert(std::atomic<std::uint64_t>::is_always_lock_free, "shared atomics must be lock-free");
static_assert(std::atomic<std::uint32_t>::is_always_lock_free, "shared atomics must be lock-free");

// Simulator side. Single writer per object.
class ShmSensorWriter {
 public:
  ShmSensorWriter() = default;
  ~ShmSensorWriter();
  ShmSensorWriter(const ShmSensorWriter&) = delete;
  ShmSensorWriter& operator=(const ShmSensorWriter&) = delete;

  // Creates (replacing an old one of the same name), sizes and maps the object. name: "/x",
  // one slash. False with error() on failure.
  bool create(const char* name);
  const char* error() const { return error_; }

  // The slot to render the next frame into (width, height and bgr; seq and stamp are set at
  // commit). Must be followed by camera_commit().
  CameraFrame& camera_begin();
  // Publishes the frame begun last, stamped stamp_ns [ns]; returns its seq.
  std::uint64_t camera_commit(TimeNs stamp_ns);
  // One copy of f (width x height pixels) into the next slot, then commit.
  std::uint64_t publish_camera(const CameraFrame& f);
  // One IMU sample; returns its seq.
  std::uint64_t publish_imu(const ImuSample& s);

 private:
  ShmSensorLayout* map_ = nullptr;
  char name_[64] = {};
  char error_[160] = {};
  std::uint64_t camera_seq_ = 0;
  std::uint64_t imu_seq_ = 0;
  std::uint32_t open_version_ = 0;  // version of the slot begun, before it went odd
};

class ShmSensorReader;

// hal::Camera over the link. latest(): the newest frame, copied once into this object's frame
// (allocated at open); the same frame (same seq) again when nothing new was written; nullptr
// before the first.
class ShmCamera final : public Camera {
 public:
  static constexpr int kMaxTries = 3;
  const CameraFrame* latest() override;
  std::uint64_t torn_retries() const { return torn_retries_; }  // copies the writer lapped
  std::uint64_t torn_drops() const { return torn_drops_; }  // newest frame given up after kMaxTries

 private:
  friend class ShmSensorReader;
  const ShmSensorLayout* map_ = nullptr;
  std::unique_ptr<CameraFrame> frame_;
  std::uint64_t last_ = 0;  // seq of frame_
  std::uint64_t torn_retries_ = 0;
  std::uint64_t torn_drops_ = 0;
};

// hal::Imu over the link. read(): the newest sample (valid=false before the first); the same
// sample (same stamp) again when nothing new was written.
class ShmImu final : public Imu {
 public:
  static constexpr int kMaxTries = 3;
  ImuSample read() override;
  std::uint64_t seq() const { return last_; }  // seq of the sample read() returns
  std::uint64_t torn_retries() const { return torn_retries_; }

 private:
  friend class ShmSensorReader;
  const ShmSensorLayout* map_ = nullptr;
  ImuSample sample_{};
  std::uint64_t last_ = 0;
  std::uint64_t torn_retries_ = 0;
};

// Controller side: maps an existing object read-only and hands out the two devices.
class ShmSensorReader {
 public:
  ShmSensorReader() = default;
  ~ShmSensorReader();
  ShmSensorReader(const ShmSensorReader&) = delete;
  ShmSensorReader& operator=(const ShmSensorReader&) = delete;

  // Maps the object the writer created. False with error() (naming the object and what was
  // wrong: missing, wrong size, wrong magic or version) on failure; call again to retry.
  bool open(const char* name);
  const char* error() const { return error_; }
  ShmCamera& camera() { return camera_; }
  ShmImu& imu() { return imu_; }

 private:
  void unmap();
  const ShmSensorLayout* map_ = nullptr;
  ShmCamera camera_;
  ShmImu imu_;
  char error_[200] = {};
};

}  // namespace carril::hal
