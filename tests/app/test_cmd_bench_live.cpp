// `luxloc bench live`: a short real-time run of the simulator prints latency, CPU and memory.
#include <catch2/catch.hpp>

#include "test_support.hpp"

using namespace luxloc::test;

TEST_CASE("bench live prints the latency percentiles, the CPU per second of data and the peak memory", "[app][bench]") {
  const auto r = run_luxloc("bench live --duration 2 --width 640 --height 360");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("width=640,height=360") != std::string::npos);
  CHECK(r.output.find("IMU samples") != std::string::npos);
  CHECK(r.output.find("latency                 p50 ") != std::string::npos);
  CHECK(r.output.find(" p99 ") != std::string::npos);
  CHECK(r.output.find("cpu per second of data") != std::string::npos);
  CHECK(r.output.find("luxloc itself") != std::string::npos);
  CHECK(r.output.find("peak RSS") != std::string::npos);
  CHECK(r.output.find("nan") == std::string::npos);
}

TEST_CASE("The sim source takes the camera size and the IMU rate, and refuses bad ones", "[app][bench]") {
  const auto ok = run_luxloc("run --source sim:dense,duration=1,realtime=0,width=1280,height=720,imu_rate=200 --out - -q");
  INFO(ok.output);
  REQUIRE(ok.exit_code == 0);
  for (const char* bad : {"width=1280", "width=0,height=720", "width=12.5,height=720", "imu_rate=0"}) {
    const auto r = run_luxloc(std::string("run --source sim:dense,duration=1,") + bad + " --out /dev/null -q");
    INFO(bad << ": " << r.output);
    CHECK(r.exit_code == 2);
  }
}
