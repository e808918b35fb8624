#include "hal/linux/ShmSensorLink.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <new>

namespace carril::hal {

namespace {

// '/' and 1 to 62 of [A-Za-z0-9_.-], not "/." or "/.." (which name /dev/shm or /dev itself).
bool name_ok(const char* name) {
  if (name == nullptr || name[0] != '/' || name[1] == '\0' || std::strlen(name) >= 64) return false;
  if (std::strcmp(name, "/.") == 0 || std::strcmp(name, "/..") == 0) return false;
  for (const char* c = name + 1; *c != '\0'; ++c) {
    const bool ok = (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') ||
                    (*c >= '0' && *c <= '9') || *c == '_' || *c == '-' || *c == '.';
    if (!ok) return false;
  }
  return true;
}

std::size_t frame_bytes(const CameraFrame& f) {
  return std::size_t(f.width) * f.height * 3;
}

}  // namespace

// --- Writer ---

ShmSensorWriter::~ShmSensorWriter() {
  if (map_ != nullptr) {
    munmap(map_, sizeof(ShmSensorLayout));
    shm_unlink(name_);
  }
}

bool ShmSensorWriter::create(const char* name) {
  if (map_ != nullptr) return std::snprintf(error_, sizeof error_, "already created"), false;
  if (!name_ok(name)) {
    std::snprintf(error_, sizeof error_,
                  "shared memory name '%s': expected '/' and up to 62 characters, no other '/'",
                  name != nullptr ? name : "(null)");
    return false;
  }
  // A stale object from an earlier run is replaced: readers of it see nothing new.
  shm_unlink(name);
  const int fd = shm_open(name, O_CREAT | O_EXCL | O_RDWR | O_CLOEXEC, 0600);
  if (fd < 0 || ftruncate(fd, off_t(sizeof(ShmSensorLayout))) != 0) {
    std::snprintf(error_, sizeof error_, "shared memory %s: cannot create: %s", name,
                  std::strerror(errno));
    if (fd >= 0) close(fd);
    shm_unlink(name);
    return false;
  }
  void* p = mmap(nullptr, sizeof(ShmSensorLayout), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  close(fd);
  if (p == MAP_FAILED) {
    std::snprintf(error_, sizeof error_, "shared memory %s: cannot map: %s", name,
                  std::strerror(errno));
    shm_unlink(name);
    return false;
  }
  // ftruncate zero-filled it; construct the atomics in place, then the magic goes last so a
  // reader never accepts a half-initialised object.
  map_ = static_cast<ShmSensorLayout*>(p);
  new (&map_->header.camera_latest) std::atomic<std::uint64_t>(0);
  new (&map_->header.imu_latest) std::atomic<std::uint64_t>(0);
  for (auto& s : map_->camera) new (&s.version) std::atomic<std::uint32_t>(0);
  for (auto& s : map_->imu) new (&s.version) std::atomic<std::uint32_t>(0);
  map_->header.version = ShmSensorLayout::kVersion;
  map_->header.size = sizeof(ShmSensorLayout);
  std::atomic_thread_fence(std::memory_order_release);
  map_->header.magic = ShmSensorLayout::kMagic;
  std::snprintf(name_, sizeof name_, "%s", name);
  camera_seq_ = imu_seq_ = 0;
  return true;
}

CameraFrame& ShmSensorWriter::camera_begin() {
  auto& slot = map_->camera[(camera_seq_ + 1) % kShmCameraSlots];
  open_version_ = slot.version.load(std::memory_order_relaxed);
  slot.version.store(open_version_ + 1, std::memory_order_relaxed);  // odd: being written
  std::atomic_thread_fence(std::memory_order_release);
  return slot.frame;
}

std::uint64_t ShmSensorWriter::camera_commit(TimeNs stamp_ns) {
  const std::uint64_t seq = ++camera_seq_;
  auto& slot = map_->camera[seq % kShmCameraSlots];
  slot.frame.seq = std::uint32_t(seq);
  slot.frame.stamp_ns = stamp_ns;
  slot.version.store(open_version_ + 2, std::memory_order_release);
  map_->header.camera_latest.store(seq, std::memory_order_release);
  return seq;
}

std::uint64_t ShmSensorWriter::publish_camera(const CameraFrame& f) {
  CameraFrame& dst = camera_begin();
  dst.width = f.width;
  dst.height = f.height;
  std::memcpy(dst.bgr.data(), f.bgr.data(), frame_bytes(f));
  return camera_commit(f.stamp_ns);
}

std::uint64_t ShmSensorWriter::publish_imu(const ImuSample& s) {
  const std::uint64_t seq = ++imu_seq_;
  auto& slot = map_->imu[seq % kShmImuSlots];
  const std::uint32_t v = slot.version.load(std::memory_order_relaxed);
  slot.version.store(v + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  slot.seq = seq;
  slot.sample = s;
  slot.version.store(v + 2, std::memory_order_release);
  map_->header.imu_latest.store(seq, std::memory_order_release);
  return seq;
}

// --- Readers ---

const CameraFrame* ShmCamera::latest() {
  if (map_ == nullptr) return nullptr;
  for (int attempt = 0; attempt < kMaxTries; ++attempt) {
    const std::uint64_t seq = map_->header.camera_latest.load(std::memory_order_acquire);
    if (seq == last_) break;  // nothing new (or nothing yet)
    const auto& slot = map_->camera[seq % kShmCameraSlots];
    const std::uint32_t v1 = slot.version.load(std::memory_order_acquire);
    const std::uint16_t w = slot.frame.width, h = slot.frame.height;
    const bool sane = (v1 & 1U) == 0 && w <= kMaxImageWidth && h <= kMaxImageHeight;
    if (sane) {
      // The one copy out. The writer may be overwriting the slot meanwhile (it lapped us);
      // the version check below throws such a copy away.
      frame_->width = w;
      frame_->height = h;
      frame_->stamp_ns = slot.frame.stamp_ns;
      frame_->seq = slot.frame.seq;
      std::memcpy(frame_->bgr.data(), slot.frame.bgr.data(), frame_bytes(*frame_));
      std::atomic_thread_fence(std::memory_order_acquire);
      if (slot.version.load(std::memory_order_relaxed) == v1 && frame_->seq == std::uint32_t(seq)) {
        last_ = seq;
        return frame_.get();
      }
    }
    ++torn_retries_;
    if (attempt + 1 == kMaxTries) {
      // Give up for this tick: report the previous seq so the firmware sees nothing new (the
      // pixels may be torn, but a frame whose seq did not change is not processed again).
      ++torn_drops_;
      frame_->seq = std::uint32_t(last_);
    }
  }
  return last_ == 0 ? nullptr : frame_.get();
}

ImuSample ShmImu::read() {
  if (map_ == nullptr) return ImuSample{};
  for (int attempt = 0; attempt < kMaxTries; ++attempt) {
    const std::uint64_t seq = map_->header.imu_latest.load(std::memory_order_acquire);
    if (seq == last_) break;
    const auto& slot = map_->imu[seq % kShmImuSlots];
    const std::uint32_t v1 = slot.version.load(std::memory_order_acquire);
    const ImuSample s = slot.sample;
    const std::uint64_t sseq = slot.seq;
    std::atomic_thread_fence(std::memory_order_acquire);
    if ((v1 & 1U) == 0 && slot.version.load(std::memory_order_relaxed) == v1 && sseq == seq) {
      sample_ = s;
      last_ = seq;
      break;
    }
    ++torn_retries_;
  }
  return sample_;
}

ShmSensorReader::~ShmSensorReader() {
  unmap();
}

void ShmSensorReader::unmap() {
  if (map_ != nullptr) munmap(const_cast<ShmSensorLayout*>(map_), sizeof(ShmSensorLayout));
  map_ = nullptr;
  camera_.map_ = nullptr;
  imu_.map_ = nullptr;
}

bool ShmSensorReader::open(const char* name) {
  unmap();
  if (!name_ok(name)) {
    std::snprintf(error_, sizeof error_,
                  "shared memory name: expected '/' and 1 to 62 letters, digits, '_', '-' or "
                  "'.', not /. or /..");
    return false;
  }
  const int fd = shm_open(name, O_RDONLY | O_CLOEXEC | O_NOFOLLOW, 0);
  if (fd < 0) {
    std::snprintf(error_, sizeof error_,
                  "shared memory %s: cannot open: %s (is the simulator running with --hil?)", name,
                  std::strerror(errno));
    return false;
  }
  struct stat st {};
  if (fstat(fd, &st) != 0) {
    std::snprintf(error_, sizeof error_, "shared memory %s: cannot stat: %s", name,
                  std::strerror(errno));
    close(fd);
    return false;
  }
  // The camera and IMU steer the robot: only a segment of this user that nobody else can write.
  if (!S_ISREG(st.st_mode) || st.st_uid != geteuid() || (st.st_mode & 0022) != 0) {
    std::snprintf(error_, sizeof error_,
                  "shared memory %s: owner uid %u, mode %04o: expected a segment of uid %u (this "
                  "controller's user) that group and others cannot write",
                  name, unsigned(st.st_uid), unsigned(st.st_mode & 07777), unsigned(geteuid()));
    close(fd);
    return false;
  }
  if (std::size_t(st.st_size) != sizeof(ShmSensorLayout)) {
    std::snprintf(error_, sizeof error_,
                  "shared memory %s: size %lld bytes, expected %zu (a writer of another layout "
                  "version?)",
                  name, static_cast<long long>(st.st_size), sizeof(ShmSensorLayout));
    close(fd);
    return false;
  }
  void* p = mmap(nullptr, sizeof(ShmSensorLayout), PROT_READ, MAP_SHARED, fd, 0);
  close(fd);
  if (p == MAP_FAILED) {
    std::snprintf(error_, sizeof error_, "shared memory %s: cannot map: %s", name,
                  std::strerror(errno));
    return false;
  }
  map_ = static_cast<const ShmSensorLayout*>(p);
  std::atomic_thread_fence(std::memory_order_acquire);
  if (map_->header.magic != ShmSensorLayout::kMagic ||
      map_->header.version != ShmSensorLayout::kVersion) {
    std::snprintf(error_, sizeof error_,
                  "shared memory %s: magic 0x%08X version %u, expected 0x%08X version %u (not "
                  "written yet, or by another program)",
                  name, map_->header.magic, map_->header.version, ShmSensorLayout::kMagic,
                  ShmSensorLayout::kVersion);
    unmap();
    return false;
  }
  if (!camera_.frame_) camera_.frame_ = std::make_unique<CameraFrame>();
  camera_.map_ = map_;
  camera_.last_ = 0;
  imu_.map_ = map_;
  imu_.last_ = 0;
  imu_.sample_ = ImuSample{};
  error_[0] = '\0';
  return true;
}

}  // namespace carril::hal
