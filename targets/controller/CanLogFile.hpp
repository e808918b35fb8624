#pragma once
// --can-log FILE: the CAN log tap's records written as candump -l lines by the slow rate group
// (never the control loop), into FILE.part while running, renamed to FILE once complete, so a
// reader never sees half a log under the final name.
#include <cstdio>
#include <string>

#include "hal/can/CanLogTap.hpp"
#include "loader/SafeCreate.hpp"

namespace carril::controller {

class CanLogFile {
 public:
  // Init: creates FILE.part for `tap`'s records (a leftover one of ours from a killed run is
  // replaced; a symlink or another user's file there is refused). False with error() set when
  // it cannot be written.
  bool open(const char* path, hal::CanLogTap& tap) {
    path_ = path;
    part_ = path_ + ".part";
    tap_ = &tap;
    f_ = loader::open_new_output(part_, error_);
    return f_ != nullptr;
  }
  // Why open() failed.
  const std::string& error() const { return error_; }
  // Slow task (and once more after the loop stopped): writes what the tap holds.
  void run() {
    if (f_ == nullptr || tap_ == nullptr) return;
    lines_ += tap_->drain([this](const char* line, std::size_t n) { std::fwrite(line, 1, n, f_); });
  }
  // Writes the rest and renames FILE.part to FILE; false when a write or the rename failed.
  bool close() {
    if (f_ == nullptr) return true;
    run();
    const bool ok = std::fclose(f_) == 0 && std::rename(part_.c_str(), path_.c_str()) == 0;
    f_ = nullptr;
    return ok;
  }
  bool is_open() const { return f_ != nullptr; }
  const std::string& path() const { return path_; }
  std::size_t lines() const { return lines_; }

 private:
  std::string path_, part_, error_;
  hal::CanLogTap* tap_ = nullptr;
  std::FILE* f_ = nullptr;
  std::size_t lines_ = 0;
};

}  // namespace carril::controller
