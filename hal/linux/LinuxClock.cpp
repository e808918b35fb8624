#include "hal/linux/LinuxClock.hpp"

#include <cerrno>
#include <ctime>

namespace carril::hal {

namespace {
TimeNs read_monotonic() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return TimeNs{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}
}  // namespace

TimeNs LinuxClock::now_ns() const {
  return read_monotonic();
}

TimeNs LinuxClock::cpu_now_ns() const {
  return read_monotonic();
}

void LinuxClock::sleep_until_ns(TimeNs t) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(t / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(t % 1'000'000'000);
  // Restart after signals; an absolute deadline does not drift when interrupted.
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

}  // namespace carril::hal
