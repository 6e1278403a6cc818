// Stripe decoder (core/vlc/stripe_decoder.cpp) on small hand-made frames: one behaviour
// per case. Rendered and real frames: test_stripe_decoder_frames.cpp.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "core/vlc/stripe_decoder.hpp"

using namespace luxloc;

namespace {

CameraModel test_camera() {
  CameraModel c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 500;
  c.cx = 320;
  c.cy = 240;
  c.row_time_s = 25e-6;
  c.exposure_s = 50e-6;
  return c;
}

LedMap test_map() {
  std::vector<Led> leds;
  const double freqs[] = {1200, 1500, 1900, 2300, 2800, 3500};
  for (int i = 0; i < 6; ++i) {
    Led l;
    l.id = 10 + i;
    l.freq_hz = freqs[i];
    l.p_inW = Eigen::Vector3d(i, 0, 3);
    leds.push_back(l);
  }
  return LedMap(leds, "test");
}

// A tiny rolling-shutter renderer: an ellipse (centre, semi-axes a, b, rotation) whose rows
// are lit by a square wave sampled over each row's exposure window, on a noisy background.
struct Blob {
  Eigen::Vector2d c;
  double a, b, angle;
  double freq_hz, duty = 0.5, phase = 0.0, level = 200.0;
};

cv::Mat render(const CameraModel& cam, const std::vector<Blob>& blobs, double noise, std::mt19937_64& rng) {
  cv::Mat img(cam.height, cam.width, CV_8UC1);
  std::normal_distribution<double> g(8.0, noise);
  for (int r = 0; r < img.rows; ++r)
    for (int u = 0; u < img.cols; ++u) img.at<uchar>(r, u) = cv::saturate_cast<uchar>(g(rng));
  for (const Blob& bl : blobs) {
    const double ca = std::cos(bl.angle), sa = std::sin(bl.angle);
    const double ext = std::max(bl.a, bl.b) + 2.0;
    const int r_lo = std::max(0, static_cast<int>(bl.c.y() - ext)), r_hi = std::min(img.rows - 1, static_cast<int>(bl.c.y() + ext));
    const int u_lo = std::max(0, static_cast<int>(bl.c.x() - ext)), u_hi = std::min(img.cols - 1, static_cast<int>(bl.c.x() + ext));
    for (int r = r_lo; r <= r_hi; ++r) {
      constexpr int kSub = 16;
      double on = 0;
      for (int s = 0; s < kSub; ++s) {
        const double t = r * cam.row_time_s + cam.exposure_s * (s + 0.5) / kSub;
        const double x = t * bl.freq_hz + bl.phase;
        on += (x - std::floor(x)) < bl.duty ? 1.0 : 0.0;
      }
      on /= kSub;
      for (int u = u_lo; u <= u_hi; ++u) {
        // 4x4 supersampled coverage of the pixel by the ellipse.
        int inside = 0;
        for (int sy = 0; sy < 4; ++sy)
          for (int sx = 0; sx < 4; ++sx) {
            const double dx = u - 0.375 + 0.25 * sx - bl.c.x(), dy = r - 0.375 + 0.25 * sy - bl.c.y();
            const double x = ca * dx + sa * dy, y = -sa * dx + ca * dy;
            inside += (x * x) / (bl.a * bl.a) + (y * y) / (bl.b * bl.b) <= 1.0 ? 1 : 0;
          }
        if (inside) {
          const double v = img.at<uchar>(r, u) + bl.level * on * inside / 16.0;
          img.at<uchar>(r, u) = cv::saturate_cast<uchar>(v);
        }
      }
    }
  }
  return img;
}

const LedObservation* nearest(const std::vector<LedObservation>& obs, const Eigen::Vector2d& uv) {
  const LedObservation* best = nullptr;
  for (const auto& o : obs)
    if (!best || (o.uv - uv).norm() < (best->uv - uv).norm()) best = &o;
  return best;
}

}  // namespace

TEST_CASE("decoder: a dark or noisy frame without LEDs gives nothing", "[vlc]") {
  const CameraModel cam = test_camera();
  const StripeDecoder dec(cam, test_map());
  std::mt19937_64 rng(1);
  CHECK(dec.decode(render(cam, {}, 1.5, rng)).empty());
  CHECK(dec.decode(render(cam, {}, 4.0, rng)).empty());
  // Hot pixels (salt noise) are not blobs.
  cv::Mat img = render(cam, {}, 1.5, rng);
  std::uniform_int_distribution<int> U(0, 639), V(0, 479);
  for (int i = 0; i < 300; ++i) img.at<uchar>(V(rng), U(rng)) = 255;
  CHECK(dec.decode(img).empty());
  CHECK(dec.decode(cv::Mat()).empty());
  CHECK(dec.decode(cv::Mat(10, 10, CV_32FC1, cv::Scalar(1.0f))).empty());  // unsupported type
}

TEST_CASE("decoder: several LEDs, ids and centres, at any camera roll", "[vlc]") {
  const CameraModel cam = test_camera();
  const LedMap map = test_map();
  const StripeDecoder dec(cam, map);
  std::mt19937_64 rng(2);
  for (double angle : {0.0, 0.5, 1.2, 2.4}) {
    const std::vector<Blob> blobs = {{{150, 120}, 38, 30, angle, 1500, 0.5, 0.1},
                                     {{450, 130}, 35, 25, angle, 2800, 0.4, 0.7},
                                     {{300, 330}, 40, 34, -angle, 1900, 0.6, 0.3},
                                     {{520, 380}, 30, 22, angle + 0.3, 3500, 0.5, 0.9}};
    const auto obs = dec.decode(render(cam, blobs, 1.5, rng));
    REQUIRE(obs.size() == 4);
    for (const Blob& b : blobs) {
      const LedObservation* o = nearest(obs, b.c);
      REQUIRE(o != nullptr);
      INFO("angle " << angle << " blob at " << b.c.transpose() << " f " << b.freq_hz << " -> " << o->freq_hz << " "
                    << o->reject_reason);
      REQUIRE(o->accepted());
      CHECK(map.leds()[static_cast<std::size_t>(o->led_index)].freq_hz == b.freq_hz);
      CHECK(o->led_id == map.leds()[static_cast<std::size_t>(o->led_index)].id);
      CHECK(std::abs(o->freq_hz - b.freq_hz) / b.freq_hz < 0.03);
      CHECK((o->uv - b.c).norm() < 0.5);  // envelope centre, not the bright stripes'
      CHECK(o->radius_px == Approx(std::sqrt(b.a * b.b)).epsilon(0.1));
      CHECK(o->confidence > 0.3);
      CHECK(o->confidence <= 1.0);
      CHECK_FALSE(o->touches_border);
      CHECK(o->on_fraction == Approx(b.duty).margin(0.12));
      CHECK(o->intensity_sum > 0.0);
    }
  }
}

TEST_CASE("decoder: colour and 16-bit frames are accepted", "[vlc]") {
  const CameraModel cam = test_camera();
  const StripeDecoder dec(cam, test_map());
  std::mt19937_64 rng(3);
  const cv::Mat gray = render(cam, {{{320, 240}, 40, 40, 0, 2300}}, 1.5, rng);
  cv::Mat bgr, wide;
  cv::cvtColor(gray, bgr, cv::COLOR_GRAY2BGR);
  gray.convertTo(wide, CV_16U, 256.0);
  for (const cv::Mat& img : {bgr, wide}) {
    const auto obs = dec.decode(img);
    REQUIRE(obs.size() == 1);
    CHECK(obs[0].led_id == 13);
  }
}

TEST_CASE("decoder: short blobs are measured by their stripe edges, a 3rd harmonic never taken for an LED", "[vlc]") {
  // 1200 Hz at 25 us/row: 33-row period. A 40-row blob shows 1.2 periods: its 3rd harmonic
  // (3600 Hz) is near the 3500 Hz LED, and must not be reported as it. Too short for the
  // periodogram (min_periods), it is measured by its stripe edges (min_edge_periods) and
  // identified as the 1200 Hz LED; with the edge estimate off it is refused.
  const CameraModel cam = test_camera();
  const LedMap map = test_map();
  const StripeDecoder dec(cam, map);
  std::mt19937_64 rng(4);
  int identified = 0;
  for (double phase : {0.0, 0.2, 0.4, 0.6, 0.8}) {
    const auto obs = dec.decode(render(cam, {{{320, 240}, 20, 20, 0, 1200, 0.5, phase}}, 1.5, rng));
    REQUIRE(obs.size() == 1);
    INFO("phase " << phase << " f " << obs[0].freq_hz << " " << obs[0].reject_reason);
    if (!obs[0].accepted()) {
      CHECK(obs[0].reject_reason == "too few rows");  // the edges did not give a consistent period
      continue;
    }
    ++identified;
    CHECK(map.leds()[static_cast<std::size_t>(obs[0].led_index)].freq_hz == 1200.0);
    CHECK(std::abs(obs[0].freq_hz - 1200.0) < 0.02 * 1200.0);
  }
  CHECK(identified >= 3);
  StripeDecoderOptions periodogram_only;
  periodogram_only.min_edge_periods = 0.0;
  const StripeDecoder strict(cam, map, periodogram_only);
  for (double phase : {0.0, 0.2, 0.4, 0.6, 0.8}) {
    const auto obs = strict.decode(render(cam, {{{320, 240}, 20, 20, 0, 1200, 0.5, phase}}, 1.5, rng));
    REQUIRE(obs.size() == 1);
    CHECK_FALSE(obs[0].accepted());
    CHECK(obs[0].reject_reason == "too few rows");
  }
  // The same LED with enough rows is decoded.
  const auto big = dec.decode(render(cam, {{{320, 240}, 50, 50, 0, 1200, 0.5, 0.3}}, 1.5, rng));
  REQUIRE(big.size() == 1);
  CHECK(big[0].led_id == 10);
}

TEST_CASE("decoder: one bright stripe across the disc, or under two periods, is measured by its edges", "[vlc]") {
  // 1200 Hz at 25 us/row: a 33-row period on a 46-row disc. At some phases a single bright
  // stripe crosses the middle and the rest of the disc is dark: its chord ends pin only 4
  // boundary sectors, yet the sharp fit holds and the stripe's width (duty x period) gives
  // the LED. At 1500 Hz (27 rows) the same disc shows 1.7 periods, where the periodogram's
  // sinusoid is biased by the square wave's harmonics; three stripe edges are not.
  const CameraModel cam = test_camera();
  const LedMap map = test_map();
  const StripeDecoder dec(cam, map);
  std::mt19937_64 rng(9);
  for (const double f : {1200.0, 1500.0}) {
    int identified = 0, wrong = 0;
    for (int k = 0; k < 20; ++k) {
      const auto obs = dec.decode(render(cam, {{{320.3, 240.6}, 23, 23, 0, f, 0.5, 0.05 * k}}, 1.5, rng));
      REQUIRE(obs.size() == 1);
      INFO("f " << f << " phase " << 0.05 * k << ": " << obs[0].freq_hz << " Hz " << obs[0].reject_reason);
      if (!obs[0].accepted()) continue;
      ++identified;
      if (map.leds()[static_cast<std::size_t>(obs[0].led_index)].freq_hz != f) ++wrong;
      CHECK(std::abs(obs[0].freq_hz - f) < 0.02 * f);
    }
    INFO("f " << f << ": " << identified << " of 20 phases identified");
    CHECK(wrong == 0);
    CHECK(identified >= 19);
  }
}

TEST_CASE("decoder: a frequency not in the map is rejected", "[vlc]") {
  const CameraModel cam = test_camera();
  const StripeDecoder dec(cam, test_map());
  std::mt19937_64 rng(5);
  const auto obs = dec.decode(render(cam, {{{320, 240}, 40, 40, 0, 3150}}, 1.5, rng));  // between 2800 and 3500
  REQUIRE(obs.size() == 1);
  CHECK(obs[0].reject_reason == "no map match");
  CHECK(obs[0].freq_hz == Approx(3150).epsilon(0.02));
  // Without a map the frequency is still measured (calibration), never matched.
  StripeDecoderOptions o;
  o.min_freq_hz = 1000;
  o.max_freq_hz = 4000;
  const StripeDecoder bare(cam, LedMap(), o);
  const auto b = bare.decode(render(cam, {{{320, 240}, 40, 40, 0, 2300}}, 1.5, rng));
  REQUIRE(b.size() == 1);
  CHECK(b[0].reject_reason == "no map match");
  CHECK(b[0].freq_hz == Approx(2300).epsilon(0.02));
}

TEST_CASE("decoder: a steady light (no stripes) is not an LED", "[vlc]") {
  const CameraModel cam = test_camera();
  const StripeDecoder dec(cam, test_map());
  std::mt19937_64 rng(6);
  // duty 1: always on.
  const auto obs = dec.decode(render(cam, {{{320, 240}, 40, 40, 0, 2300, 1.0}}, 1.5, rng));
  REQUIRE(obs.size() == 1);
  CHECK_FALSE(obs[0].accepted());
  CHECK(obs[0].reject_reason == "no stripes");
}

TEST_CASE("decoder: a blob cut by the border is decoded when it shows enough rows, and flagged", "[vlc]") {
  const CameraModel cam = test_camera();
  const LedMap map = test_map();
  const StripeDecoder dec(cam, map);
  std::mt19937_64 rng(7);
  // Centre just inside the top border: half the disc visible (45 rows, 3.9 periods).
  const auto top = dec.decode(render(cam, {{{300, 5}, 45, 45, 0, 2800}}, 1.5, rng));
  REQUIRE(top.size() == 1);
  CHECK(top[0].accepted());
  CHECK(top[0].led_id == 14);
  CHECK(top[0].touches_border);
  CHECK((top[0].uv - Eigen::Vector2d(300, 5)).norm() < 2.0);  // the ellipse fit sees the whole arc
  // A sliver at the left border.
  const auto left = dec.decode(render(cam, {{{-30, 240}, 40, 40, 0, 2800}}, 1.5, rng));
  for (const auto& o : left) {
    CHECK(o.touches_border);
    if (o.accepted()) CHECK(o.led_id == 14);  // identified or refused, never misidentified
  }
  // Saturated core: clipped stripes are still periodic.
  const auto sat = dec.decode(render(cam, {{{320, 240}, 40, 40, 0.3, 1900, 0.5, 0.0, 600.0}}, 1.5, rng));
  REQUIRE(sat.size() == 1);
  CHECK(sat[0].saturated);
  CHECK(sat[0].led_id == 12);
}

TEST_CASE("decoder: two LEDs overlapping in the image are refused, not misread", "[vlc]") {
  const CameraModel cam = test_camera();
  const StripeDecoder dec(cam, test_map());
  std::mt19937_64 rng(8);
  const auto obs = dec.decode(
      render(cam, {{{300, 240}, 35, 35, 0, 1500}, {{345, 250}, 30, 30, 0, 3500, 0.5, 0.5}}, 1.5, rng));
  REQUIRE(obs.size() == 1);  // one merged blob
  CHECK_FALSE(obs[0].accepted());
}

TEST_CASE("decoder options: derived kernel and search range follow the map and the camera", "[vlc]") {
  const CameraModel cam = test_camera();
  const StripeDecoder dec(cam, test_map());
  // Longest dark stripe: 0.5 / (1200 Hz * 25 us) = 16.7 rows (+ blur margin).
  CHECK(dec.closing_rows() >= 17);
  CHECK(dec.closing_rows() <= 23);
  CHECK(dec.max_period_rows() > 1.0 / (1200 * 25e-6));
  CHECK(dec.min_period_rows() < 1.0 / (3500 * 25e-6));
  // Tolerance capped by the map's spacing (1500/1200 .. 3500/2800: 21.7 % smallest gap).
  CHECK(dec.rel_tolerance() <= 0.05);
}
