#pragma once
// The outcome of an init-time check (configuration, task table, device bring-up): ok, or an error
// message that names what failed, the value and what was expected. Fixed size: no heap, usable
// where exceptions are off. Checks run in every build type (not asserts).
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <span>

namespace carril::fw {

template <class Cfg>
struct Param;  // firmware/core/Param.hpp

class Status {
 public:
  static constexpr std::size_t kMaxText = 240;

  static Status ok() { return Status{}; }
  // printf-style message: "behavior.lost_frames: 0 frames, expected 1 to 100".
  [[gnu::format(printf, 1, 2)]] static Status error(const char* fmt, ...) {
    Status s;
    std::va_list args;
    va_start(args, fmt);
    std::vsnprintf(s.text_, kMaxText, fmt, args);
    va_end(args);
    if (s.text_[0] == '\0') s.text_[0] = '?';
    return s;
  }
  bool is_ok() const { return text_[0] == '\0'; }
  explicit operator bool() const { return is_ok(); }
  // The error message ("" when ok).
  const char* message() const { return text_; }

 private:
  char text_[kMaxText] = {};
};

// Range checks over one config struct, keeping the first failure:
//   return Checks("limits").range("max_speed_mps", max_speed_mps, 0.01, 10.0, "m/s").result();
class Checks {
 public:
  explicit Checks(const char* scope) : scope_(scope) {}
  Checks& range(const char* field, double v, double lo, double hi, const char* unit) {
    if (status_.is_ok() && !(std::isgreaterequal(v, lo) && std::islessequal(v, hi))) {
      status_ =
          Status::error("%s.%s: %g %s, expected %g to %g %s", scope_, field, v, unit, lo, hi, unit);
    }
    return *this;
  }
  // Every range of a struct's settings table (firmware/core/Param.hpp), in table order.
  template <class Cfg>
  Checks& params(const Cfg& c, std::span<const Param<Cfg>> table);
  // A nested struct's own validate().
  Checks& nested(const Status& s) {
    if (status_.is_ok() && !s.is_ok()) status_ = s;
    return *this;
  }
  Checks& fail_if(bool bad, const char* field, const char* why) {
    if (status_.is_ok() && bad) status_ = Status::error("%s.%s: %s", scope_, field, why);
    return *this;
  }
  const Status& result() const { return status_; }

 private:
  const char* scope_;
  Status status_;
};

}  // namespace carril::fw
