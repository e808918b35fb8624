#pragma once
// A mission's named phase (a static string, e.g. "transit") and the change of it that the runner
// reports as an event once (Mission::take_phase_change). The missions keep their own State enum
// beside it; entering a new state counts as a change even when its phase name stays the same.

namespace carril::fw {

class MissionPhase {
 public:
  // Moves to `phase`; reported when the name differs or `new_state` (the mission changed state).
  void set(const char* phase, bool new_state) {
    if (new_state || phase != phase_) change_ = phase;
    phase_ = phase;
  }
  // Starts again in `phase` (a mission's enter()), reported as a change.
  void restart(const char* phase) {
    phase_ = phase;
    change_ = phase;
  }
  // The phase entered since the last call, or nullptr.
  const char* take_change() {
    const char* p = change_;
    change_ = nullptr;
    return p;
  }
  const char* current() const { return phase_; }  // the phase now

 private:
  const char* phase_ = "wait";
  const char* change_ = nullptr;
};

}  // namespace carril::fw
