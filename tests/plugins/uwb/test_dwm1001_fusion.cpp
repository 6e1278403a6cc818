// A DWM1001 tag's lines straight into the fusion, with no session.yaml: the anchor positions
// come from the lines, the first multilateration initialises the filter, every range then
// weighs the particles (no IMU: constant-velocity prediction).
#include <catch2/catch.hpp>
#include <cstdio>
#include <random>

#include "core/fusion/fusion_engine.hpp"
#include "plugins/uwb/dwm1001_parser.hpp"

using namespace luxloc;

TEST_CASE("DWM1001 lines -> fusion: anchors learnt from the lines, a static tag located within 0.1 m", "[uwb]") {
  const Eigen::Vector3d tag(3.1, 2.2, 1.0);
  const Eigen::Vector3d anchors[4] = {{0, 0, 2.5}, {8, 0, 2.4}, {8, 6, 2.6}, {0, 6, 2.5}};
  const char* ids[4] = {"0C8E", "1A9C", "2B01", "3D77"};
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 0.08);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::string text;
  for (int k = 0; k < 100; ++k) {  // 10 s at 10 Hz
    text += "DIST,4";
    for (int i = 0; i < 4; ++i) {
      double r = (tag - anchors[i]).norm() + n(rng);
      if (u(rng) < 0.05) r += 0.5 + 2.0 * u(rng);  // NLOS
      char buf[96];
      std::snprintf(buf, sizeof buf, ",AN%d,%s,%.2f,%.2f,%.2f,%.2f", i, ids[i], anchors[i].x(), anchors[i].y(),
                    anchors[i].z(), r);
      text += buf;
    }
    text += ",POS,3.05,2.25,0.98,70\r\n";
  }
  DropCounts drops;
  Dwm1001Parser parser(drops);
  std::vector<SensorData> data;
  // One chunk per line, 100 ms apart.
  std::size_t start = 0;
  TimeNs t = 1'000'000'000;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start) + 1;
    parser.feed(reinterpret_cast<const std::uint8_t*>(text.data() + start), end - start, t, 87.0, data);
    start = end;
    t += 100'000'000;
  }
  REQUIRE(data.size() == 400);
  SessionConfig session;
  session.device_height_m = 1.0;
  FusionEngine engine(FusionOptions{}, std::nullopt, std::nullopt, session);
  std::vector<PoseEstimate> out;
  for (const SensorData& d : data) engine.process(Sample{sample_time(d), 0, d}, out);
  engine.finish(out);
  const UwbStats& st = engine.uwb_stats();
  CHECK(st.learnt_anchors == 4);
  CHECK(st.unknown_anchor == 0);
  // The filter starts once 3 consecutive multilateration fixes agree (UwbOptions::
  // start_agreeing_fixes: 3 groups of 4 ranges, more when an NLOS range breaks agreement);
  // every later range is weighed.
  CHECK(st.start_held >= 2);
  CHECK(st.weighed > 380);
  REQUIRE(out.size() > 300);
  double worst_late = 0.0;
  for (std::size_t i = out.size() / 2; i < out.size(); ++i)
    worst_late = std::max(worst_late, (out[i].p_BinW.head<2>() - tag.head<2>()).norm());
  WARN("DWM1001 -> fusion: final error " << (out.back().p_BinW.head<2>() - tag.head<2>()).norm()
                                         << " m, worst over the last 5 s " << worst_late << " m");
  CHECK((out.back().p_BinW.head<2>() - tag.head<2>()).norm() < 0.1);
  CHECK(worst_late < 0.2);
}
