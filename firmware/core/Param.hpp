#pragma once
// A setting declared once: the member it sets, its unit, range and one-line meaning, side by side
// (PX4's module.yaml, written as C++). Each config struct lists its settings in one table, its
// params(); its validate() checks the ranges from that table, the loader (loader/Settings.cpp)
// takes the keys and types from it, and docs/configuration.md's tables are generated from it
// (carril_settings_doc; SettingsDocTest fails when they differ). The default is the member's
// initialiser in the struct, read from a default-constructed struct: written once, there.
#include <span>

#include "firmware/core/Status.hpp"

namespace carril::fw {

// What a setting is, independent of the struct it lives in.
struct ParamInfo {
  const char* name;         // the member's name, as validate() messages and files spell it
  const char* unit;         // "m", "s", "rad/s", "(fraction)"; an integer's count ("frames")
  double min;               // inclusive
  double max;               // inclusive
  const char* description;  // one line, for docs/configuration.md
  // The default is worked out when the configuration is built (from the robot's rates or the
  // mission): how, for the docs ("3 frames, at least 0.2 s"); nullptr: the member's initialiser.
  const char* derived = nullptr;
  // False: set from the robot or mission file, or worked out from them; no file key sets it.
  bool tunable = true;
};

// One row of a struct's table: a real or an integer member (exactly one is set).
template <class Cfg>
struct Param {
  ParamInfo info;
  double Cfg::*number = nullptr;
  int Cfg::*integer = nullptr;

  bool is_integer() const { return integer != nullptr; }
  double get(const Cfg& c) const {
    return number != nullptr ? c.*number : static_cast<double>(c.*integer);
  }
  // An integer setting takes v as read (the loader reads integers exactly).
  void set(Cfg& c, double v) const {
    if (number != nullptr) {
      c.*number = v;
    } else {
      c.*integer = static_cast<int>(v);
    }
  }
};

template <class Cfg>
constexpr Param<Cfg> param(double Cfg::*member, ParamInfo info) {
  return Param<Cfg>{info, member, nullptr};
}
template <class Cfg>
constexpr Param<Cfg> param(int Cfg::*member, ParamInfo info) {
  return Param<Cfg>{info, nullptr, member};
}

// A row whose name is the member's, written once: CARRIL_PARAM(Cfg, lost_frames, "frames", 1,
// 100, "frames without tape before the tape is lost").
#define CARRIL_PARAM(Cfg, member, ...) \
  ::carril::fw::param(&Cfg::member, ::carril::fw::ParamInfo{#member, __VA_ARGS__})

template <class Cfg>
Checks& Checks::params(const Cfg& c, std::span<const Param<Cfg>> table) {
  for (const Param<Cfg>& p : table) {
    range(p.info.name, p.get(c), p.info.min, p.info.max, p.info.unit);
  }
  return *this;
}

}  // namespace carril::fw
