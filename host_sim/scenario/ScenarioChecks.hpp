#pragma once
// Checks across sections of a loaded scenario, made after every key has been read: the robot's
// start footprint must be clear of obstacles and walls, and the detector must tell the tape and
// the end mark from the floor and from each other. Each throws strict::LoadError with the usual
// "<file>:<line>: <key>: expected ..., got ..." message.
#include "host_sim/scenario/Scenario.hpp"
#include "loader/StrictYaml.hpp"

namespace carril::sim {

namespace strict = loader::strict;

// `root` is the scenario document (for the line and key of the message).
void check_start_clear(const strict::Node& root, const Scenario& s);
void check_colours(const strict::Node& root, const Scenario& s);

}  // namespace carril::sim
