#pragma once
// A Mission whose every output is scripted by the test, recording how the runner calls it.
#include <vector>

#include "firmware/mission/Mission.hpp"

namespace carril::fw::test {

class ScriptedMission final : public Mission {
 public:
  const char* name() const override { return "scripted"; }
  void enter(const MissionContext& ctx) override {
    ++enters;
    enter_t_s = ctx.t_s;
  }
  void exit() override { ++exits; }
  MissionOutput update(const MissionContext& ctx) override {
    contexts.push_back(ctx);
    saw_obstacle.push_back(ask_obstacle ? ctx.obstacle_ahead() : false);
    MissionOutput o = next;
    next.fault = Fault::None;  // a scripted fault is reported once
    if (next_state) {
      st = *next_state;
      next_state = nullptr;
    }
    if (next_phase != nullptr) {
      st.phase = next_phase;
      pending_phase = next_phase;
      next_phase = nullptr;
    }
    return o;
  }
  MissionState state() const override { return st; }
  const char* take_phase_change() override {
    const char* p = pending_phase;
    pending_phase = nullptr;
    return p;
  }
  void relocalised() override { ++relocalisations; }
  void counters(MissionCounters& out) const override {
    out.clear();
    out.push_back({"updates", static_cast<std::uint32_t>(contexts.size())});
  }

  // Script.
  MissionOutput next;
  const MissionState* next_state = nullptr;  // entered during the next update
  const char* next_phase = nullptr;          // entered during the next update
  bool ask_obstacle = false;
  MissionState st{MissionStatus::Starting, 0, "WAIT", "idle", false};
  // Record.
  int enters = 0, exits = 0, relocalisations = 0;
  double enter_t_s = -1.0;
  std::vector<MissionContext> contexts;
  std::vector<bool> saw_obstacle;

 private:
  const char* pending_phase = nullptr;
};

}  // namespace carril::fw::test
