// GoogleTest main for every carril test binary: floating-point traps on, so an invalid
// operation, a division by zero or an overflow stops the test where it happens.
#include <gtest/gtest.h>

#include "host_sim/app/FpTraps.hpp"

int main(int argc, char** argv) {
  carril::sim::enable_fp_traps();
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
