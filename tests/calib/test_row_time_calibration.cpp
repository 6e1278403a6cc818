// Row-time calibration (calib/row_time_calibration.cpp): a real full-frame stripe pattern
// with a published readout time, rendered discs, and the refusals.
#include <catch2/catch.hpp>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <stdexcept>

#include "calib/row_time_calibration.hpp"
#include "test_support.hpp"

using namespace luxloc;
using namespace luxloc::calib;

namespace {

// A disc of radius `radius_px` lit by a 50 % square wave at `freq_hz`, each row integrating
// `exposure_s` from its start (row r starts at r * row_time_s), on a noisy dark background.
cv::Mat render_disc(double radius_px, double freq_hz, double row_time_s, double exposure_s, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(10.0, 2.0);
  cv::Mat img(480, 640, CV_8UC1);
  const double cu = 321.3, cv_ = 238.7;
  for (int r = 0; r < img.rows; ++r) {
    constexpr int kSub = 16;
    double on = 0.0;
    for (int s = 0; s < kSub; ++s) {
      const double t = r * row_time_s + exposure_s * (s + 0.5) / kSub;
      on += (t * freq_hz - std::floor(t * freq_hz)) < 0.5 ? 1.0 : 0.0;
    }
    on /= kSub;
    for (int u = 0; u < img.cols; ++u) {
      const double d = std::hypot(u - cu, r - cv_);
      const double cover = std::clamp(radius_px + 0.5 - d, 0.0, 1.0);
      img.at<uchar>(r, u) = cv::saturate_cast<uchar>(noise(rng) + 180.0 * on * cover);
    }
  }
  return img;
}

}  // namespace

TEST_CASE("row time from a real full-frame stripe pattern (Nikon 1 J1, 1000 Hz): 15.730 ms / 1080 rows within 0.3 %",
          "[calib][vlc]") {
  const auto path = test::shared_dir() / "realdata/rolling_shutter_readout/frame_example.png";
  const cv::Mat img = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  REQUIRE_FALSE(img.empty());
  RowTimeOptions o;
  o.led_freq_hz = 1000.0;
  const RowTimeFrame f = measure_row_time(img, o);
  INFO(f.reason << ": " << f.row_time_s * 1e6 << " us, period " << f.period_rows << " rows, " << f.periods
                << " periods, rows " << f.first_row << "-" << f.last_row);
  REQUIRE(f.valid);
  const double published_s = 15.730e-3 / 1080.0;  // gyroflow's readout time for this clip
  CHECK(std::abs(f.row_time_s - published_s) / published_s < 0.003);
  CHECK(f.periods > 14.0);  // the whole frame was used, not a part of it
  CHECK(f.row_time_sigma_s < 0.001 * f.row_time_s);
}

TEST_CASE("row time from rendered discs: within 0.5 % at 20 and 40 us rows, refusals say why", "[calib][vlc]") {
  RowTimeOptions o;
  o.led_freq_hz = 1200.0;
  for (const double rt : {20e-6, 40e-6}) {
    std::vector<RowTimeFrame> frames;
    for (std::uint64_t seed = 1; seed <= 3; ++seed) frames.push_back(measure_row_time(render_disc(150, 1200, rt, 60e-6, seed), o));
    for (const RowTimeFrame& f : frames) {
      INFO("row time " << rt * 1e6 << " us: " << f.reason << " " << f.row_time_s * 1e6 << " us, " << f.periods
                       << " periods");
      REQUIRE(f.valid);
      CHECK(std::abs(f.row_time_s - rt) / rt < 0.005);
    }
    const RowTimeSummary s = summarize_row_times(frames);
    CHECK(s.used == 3);
    CHECK(std::abs(s.row_time_s - rt) / rt < 0.005);
  }
  // A small disc: 40 rows hold 1.2 periods of 33 rows.
  const RowTimeFrame small = measure_row_time(render_disc(20, 1200, 25e-6, 60e-6, 4), o);
  CHECK_FALSE(small.valid);
  CHECK(small.reason.find("too few stripe periods") != std::string::npos);
  // No light at all.
  const RowTimeFrame dark = measure_row_time(render_disc(0, 1200, 25e-6, 60e-6, 5), o);
  CHECK_FALSE(dark.valid);
  CHECK(dark.reason == "no light above the background");
  // A steady light (no blinking) has no stripes.
  RowTimeOptions steady = o;
  const RowTimeFrame flat = measure_row_time(render_disc(150, 1e-3, 25e-6, 60e-6, 6), steady);
  CHECK_FALSE(flat.valid);
  // Options are checked.
  RowTimeOptions bad;
  CHECK_THROWS_AS(measure_row_time(render_disc(150, 1200, 25e-6, 60e-6, 7), bad), std::invalid_argument);
}

TEST_CASE("row time summary: median and MAD spread of the frames that count", "[calib]") {
  std::vector<RowTimeFrame> f(5);
  const double v[] = {30.0e-6, 30.2e-6, 29.9e-6, 45.0e-6, 30.1e-6};
  for (int i = 0; i < 5; ++i) {
    f[static_cast<std::size_t>(i)].valid = true;
    f[static_cast<std::size_t>(i)].row_time_s = v[i];
  }
  f.push_back(RowTimeFrame{});  // refused: not counted
  const RowTimeSummary s = summarize_row_times(f);
  CHECK(s.frames == 6);
  CHECK(s.used == 5);
  CHECK(s.row_time_s == Approx(30.1e-6));  // the outlier does not move the median
  CHECK(s.spread_s == Approx(1.4826 * 0.1e-6).epsilon(0.01));
  CHECK(s.min_s == Approx(29.9e-6));
  CHECK(s.max_s == Approx(45.0e-6));
  CHECK(summarize_row_times({}).used == 0);
}
