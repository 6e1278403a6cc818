#include <catch2/catch.hpp>

#include "test_support.hpp"

using namespace luxloc::test;

TEST_CASE("luxloc bench pf prints the time per step and per particle", "[filter]") {
  for (const char* filter : {"pf", "gpf"}) {
    const CommandResult r =
        run_luxloc(std::string("bench pf --particles 5000 --threads 1 --steps 5 --filter ") + filter);
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    REQUIRE(r.output.find("filter " + std::string(filter) + ", 5000 particles, 1 thread,") != std::string::npos);
    REQUIRE(r.output.find("time per step") != std::string::npos);
    REQUIRE(r.output.find("ns per particle-step") != std::string::npos);
    REQUIRE(r.output.find("particle-steps/s") != std::string::npos);
  }
  REQUIRE(run_luxloc("bench pf --particles 5000 --filter ekf").exit_code == 2);
  REQUIRE(run_luxloc("bench pf --particles 1").exit_code == 2);
}
