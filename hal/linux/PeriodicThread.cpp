#include "hal/linux/PeriodicThread.hpp"

#include <sched.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "hal/linux/LinuxClock.hpp"

namespace carril::hal {

bool PeriodicThread::start(const char* name, TimeNs period_ns, int priority, void (*fn)(void*),
                           void* ctx) {
  note_[0] = '\0';
  if (running_) {
    std::snprintf(note_, sizeof note_, "periodic thread '%s': already running", name_);
    return false;
  }
  if (name == nullptr) name = "";
  const int max_prio = sched_get_priority_max(SCHED_FIFO);
  if (period_ns <= 0 || fn == nullptr || priority < 0 || priority > max_prio) {
    std::snprintf(note_, sizeof note_,
                  "periodic thread '%s': period %lld ns (expected > 0 ns), priority %d "
                  "(expected 0 to %d), fn %s",
                  name, static_cast<long long>(period_ns), priority, max_prio,
                  fn == nullptr ? "null (expected a function)" : "set");
    return false;
  }
  std::snprintf(name_, sizeof name_, "%s", name);
  fn_ = fn;
  ctx_ = ctx;
  period_ns_ = period_ns;
  stop_.store(false);
  cycles_.store(0);
  missed_.store(0);

  int rc = 0;
  bool fifo_refused = false;
  if (priority > 0) {
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    // Explicit: otherwise the thread inherits the creator's policy and ignores these.
    pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED);
    pthread_attr_setschedpolicy(&attr, SCHED_FIFO);
    sched_param sp{};
    sp.sched_priority = priority;
    pthread_attr_setschedparam(&attr, &sp);
    rc = pthread_create(&thread_, &attr, &PeriodicThread::entry, this);
    pthread_attr_destroy(&attr);
    if (rc == 0) policy_ = Policy::Fifo;
    // No CAP_SYS_NICE, or RLIMIT_RTPRIO too low: run anyway, and say so.
    fifo_refused = rc == EPERM;
    if (fifo_refused) {
      std::snprintf(note_, sizeof note_,
                    "periodic thread '%s': SCHED_FIFO priority %d not permitted (%s), running "
                    "SCHED_OTHER",
                    name_, priority, std::strerror(rc));
    }
  }
  if (priority == 0 || fifo_refused) {
    rc = pthread_create(&thread_, nullptr, &PeriodicThread::entry, this);
    if (rc == 0) policy_ = Policy::Other;
  }
  if (rc != 0) {
    std::snprintf(note_, sizeof note_, "periodic thread '%s': pthread_create failed: %s", name_,
                  std::strerror(rc));
    policy_ = Policy::None;
    return false;
  }
  pthread_setname_np(thread_, name_);  // best effort: a name only helps ps and top
  running_ = true;
  return true;
}

void PeriodicThread::stop() {
  if (!running_) return;
  stop_.store(true, std::memory_order_relaxed);
  pthread_join(thread_, nullptr);
  running_ = false;
}

void* PeriodicThread::entry(void* self) {
  static_cast<PeriodicThread*>(self)->loop();
  return nullptr;
}

void PeriodicThread::loop() {
  LinuxClock clock;  // CLOCK_MONOTONIC; sleep_until_ns is clock_nanosleep(TIMER_ABSTIME)
  TimeNs next = clock.now_ns();
  while (!stop_.load(std::memory_order_relaxed)) {
    fn_(ctx_);
    cycles_.fetch_add(1, std::memory_order_relaxed);
    next += period_ns_;
    const TimeNs now = clock.now_ns();
    if (now > next) {
      // Deadlines passed while fn ran: skip them rather than run back-to-back to catch up.
      const TimeNs skipped = (now - next + period_ns_ - 1) / period_ns_;
      missed_.fetch_add(static_cast<std::uint64_t>(skipped), std::memory_order_relaxed);
      next += skipped * period_ns_;
    }
    clock.sleep_until_ns(next);
  }
}

}  // namespace carril::hal
