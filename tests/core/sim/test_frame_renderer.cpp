// Rolling-shutter frame synthesis: the square wave's on-fraction, the stripe period, the
// blob's geometry and brightness, border cuts, blackout, and rolling-shutter skew.
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "core/sim/frame_renderer.hpp"
#include "core/sim/scenario.hpp"
#include "core/sim/simulator.hpp"

using namespace luxloc;
using namespace luxloc::sim;

namespace {

// Midpoint-rule integral of the square wave over the window (the reference on_fraction must match).
double numeric_on_fraction(double f, double duty, double phase, double t, double E) {
  const int n = 200000;
  int on = 0;
  for (int i = 0; i < n; ++i) {
    const double x = f * (t + (i + 0.5) * E / n - phase);
    on += (x - std::floor(x)) < duty ? 1 : 0;
  }
  return static_cast<double>(on) / n;
}

// Amplitude of the fundamental of on_fraction(t) over one period of start times.
double fundamental(double f, double duty, double E) {
  const int n = 4096;
  std::complex<double> acc = 0.0;
  for (int i = 0; i < n; ++i) {
    const double t = (i + 0.5) / (n * f);
    acc += on_fraction(f, duty, 0.0, t, E) * std::polar(1.0, -2.0 * std::numbers::pi * i / n);
  }
  return 2.0 * std::abs(acc) / n;
}

LedMap single_led(const Eigen::Vector3d& p, double f_hz, double duty = 0.5, double hpa_deg = 60.0) {
  Led l;
  l.id = 7;
  l.freq_hz = f_hz;
  l.p_inW = p;
  l.duty = duty;
  l.half_power_angle_deg = hpa_deg;
  l.diameter_m = 0.20;
  return LedMap({l}, "test");
}

PoseAt standing_at(const Eigen::Vector3d& p, double yaw = 0.0) {
  return [p, yaw](double) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = p;
    return T;
  };
}

RenderOptions noise_free() {
  RenderOptions o;
  o.read_noise_dn = 0.0;
  o.shot_noise = false;
  return o;
}

double blob_sum(const cv::Mat& gray, double black) {
  double s = 0.0;
  for (int y = 0; y < gray.rows; ++y)
    for (int x = 0; x < gray.cols; ++x) s += std::max(0.0, gray.at<uchar>(y, x) - black);
  return s;
}

// Period (rows) of the strongest oscillation of a profile, by a fine DFT peak search
// (Hann window against leakage from the mean and the blob edges).
double dominant_period(const std::vector<double>& profile) {
  double mean = 0.0;
  for (double v : profile) mean += v;
  mean /= static_cast<double>(profile.size());
  const double n = static_cast<double>(profile.size());
  double best_p = 0.0, best = -1.0;
  for (double p = 4.0; p <= 60.0; p += 0.005) {
    std::complex<double> acc = 0.0;
    for (std::size_t i = 0; i < profile.size(); ++i)
      acc += (profile[i] - mean) * (0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * (i + 0.5) / n)) *
             std::polar(1.0, -2.0 * std::numbers::pi * static_cast<double>(i) / p);
    if (std::abs(acc) > best) {
      best = std::abs(acc);
      best_p = p;
    }
  }
  return best_p;
}

}  // namespace

TEST_CASE("on_fraction equals the numerically integrated square wave", "[sim]") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double f : {1000.0, 2500.0, 4300.0, 9000.0})
    for (double duty : {0.5, 0.3, 0.8})
      for (double E : {40e-6, 100e-6, 300e-6, 1.3e-3}) {
        const double phase = u(rng) / f, t = 10.0 + u(rng);
        INFO("f " << f << " duty " << duty << " E " << E);
        CHECK(on_fraction(f, duty, phase, t, E) == Approx(numeric_on_fraction(f, duty, phase, t, E)).margin(2e-4));
      }
  // Zero exposure: the instantaneous state; late times keep full precision.
  CHECK(on_fraction(1000.0, 0.5, 0.0, 0.0002, 0.0) == 1.0);
  CHECK(on_fraction(1000.0, 0.5, 0.0, 0.0007, 0.0) == 0.0);
  CHECK(on_fraction(1000.0, 0.5, 0.0, 3600.0 + 0.0007, 50e-6) == Approx(0.0).margin(1e-9));
  CHECK(on_fraction(1000.0, 0.5, 0.0, 3600.0 + 0.00045, 100e-6) == Approx(0.5).margin(1e-9));
}

TEST_CASE("stripe contrast falls as sinc(f * exposure), zero at f * exposure = 1 (FIELD_NOTES)", "[sim]") {
  const double square = fundamental(5000.0, 0.5, 0.0);  // 2/pi for a 0/1 square wave
  CHECK(square == Approx(2.0 / std::numbers::pi).epsilon(1e-3));
  // 100 us: ~0.64 at 5 kHz, 0 at 10 kHz; 300 us: ~0.5 at 2 kHz, 0 at 3.33 kHz.
  CHECK(fundamental(5000.0, 0.5, 100e-6) / square == Approx(0.637).margin(0.005));
  CHECK(fundamental(2000.0, 0.5, 300e-6) / square == Approx(0.504).margin(0.005));
  CHECK(fundamental(10000.0, 0.5, 100e-6) / square < 1e-6);
  CHECK(fundamental(1.0 / 300e-6, 0.5, 300e-6) / square < 1e-6);
  // At f E = 1 every row integrates exactly one period: the on-fraction is the duty, flat.
  for (double t = 0.0; t < 1e-4; t += 7e-6) CHECK(on_fraction(10000.0, 0.5, 0.0, t, 100e-6) == Approx(0.5).margin(1e-9));
}

TEST_CASE("An LED straight above: stripes of period 1/(f row_time), blob at the projected centre", "[sim]") {
  CameraModel cam = default_sim_camera();
  const Eigen::Vector3d device(2.0, 2.0, 2.0);  // 1 m below the LED: a 92 px disc, 4+ periods
  for (double f : {1500.0, 3000.0}) {
    const LedMap map = single_led({2.0, 2.0, 3.0}, f);
    std::mt19937_64 rng(1);
    const RenderedFrame fr = render_frame(cam, map, standing_at(device), 0.25, RenderOptions{}, rng, {1e-4});
    REQUIRE(fr.leds.size() == 1);
    const RenderedLed& led = fr.leds[0];
    CHECK(led.id == 7);
    CHECK(led.uv.x() == Approx(cam.cx).margin(1e-6));
    CHECK(led.uv.y() == Approx(cam.cy).margin(1e-6));
    CHECK(led.radius_px == Approx(460.0 * 0.10 / 1.0).margin(0.3));  // f r / d
    CHECK(led.fully_inside);
    CHECK(led.row_max - led.row_min == Approx(2.0 * led.radius_px).margin(0.5));
    // Row profile through the middle columns of the blob.
    std::vector<double> profile;
    for (int y = static_cast<int>(std::ceil(led.row_min)) + 2; y <= static_cast<int>(led.row_max) - 2; ++y) {
      double s = 0.0;
      for (int x = 300; x <= 340; ++x) s += fr.gray.at<uchar>(y, x);
      profile.push_back(s / 41.0);
    }
    const double expected = 1.0 / (f * cam.row_time_s);
    INFO("f " << f << " expected period " << expected);
    CHECK(dominant_period(profile) == Approx(expected).margin(0.01 * expected));
    // Bright and dark stripes both present: contrast sinc(f E) ~ 0.95..0.99 here.
    const auto [mn, mx] = std::minmax_element(profile.begin(), profile.end());
    CHECK(*mx > 200.0);
    CHECK(*mn < 40.0);
  }
}

TEST_CASE("Blob geometry and brightness follow the projection and the Lambertian channel", "[sim]") {
  CameraModel cam = default_sim_camera();
  cam.dist = {0, 0, 0, 0, 0};  // undistorted, so the area factor is exactly the pinhole's
  const RenderOptions opt = noise_free();
  // Always on (duty ~1), so the blob is a full disc.
  const auto render_at = [&](const Eigen::Vector3d& led_p, double hpa) {
    std::mt19937_64 rng(2);
    return render_frame(cam, single_led(led_p, 1000.0, 0.9999, hpa), standing_at({0, 0, 1}), 0.0, opt, rng, {});
  };
  const RenderedFrame above = render_at({0, 0, 3}, 60.0);
  REQUIRE(above.leds.size() == 1);
  // Intensity-weighted centroid at the projected centre.
  double sx = 0, sy = 0, sw = 0;
  for (int y = 0; y < above.gray.rows; ++y)
    for (int x = 0; x < above.gray.cols; ++x) {
      const double w = std::max(0.0, above.gray.at<uchar>(y, x) - opt.black_dn);
      sx += w * x;
      sy += w * y;
      sw += w;
    }
  CHECK(sx / sw == Approx(above.leds[0].uv.x()).margin(0.05));
  CHECK(sy / sw == Approx(above.leds[0].uv.y()).margin(0.05));
  // Per-pixel level of an LED straight above = peak_dn; integral = peak * pi r^2 (r = 23 px).
  CHECK(static_cast<int>(above.gray.at<uchar>(240, 320)) == Approx(opt.black_dn + opt.peak_dn).margin(1.0));
  CHECK(blob_sum(above.gray, opt.black_dn) == Approx(opt.peak_dn * std::numbers::pi * 23.0 * 23.0).epsilon(0.01));

  // 1 m to the side (world y, seen across the image): integral ratio = cos^m(phi) cos(theta) / d^2.
  for (double hpa : {60.0, 30.0}) {
    const double m = -std::log(2.0) / std::log(std::cos(hpa * std::numbers::pi / 180.0));
    const RenderedFrame ref = render_at({0, 0, 3}, hpa);
    const RenderedFrame side = render_at({0, 1.0, 3}, hpa);
    REQUIRE(side.leds.size() == 1);
    const double d2 = 1.0 + 4.0, c = 2.0 / std::sqrt(d2);
    const double expected = (std::pow(c, m) * c / d2) / (1.0 / 4.0);
    INFO("half-power angle " << hpa << " m " << m);
    CHECK(blob_sum(side.gray, opt.black_dn) / blob_sum(ref.gray, opt.black_dn) == Approx(expected).epsilon(0.02));
  }
}

TEST_CASE("An LED at the image border is cut, and one outside is absent", "[sim]") {
  const CameraModel cam = default_sim_camera();
  const RenderOptions opt = noise_free();
  // Camera x = body -y: a LED at world y = +1.45 m (2 m above) lands at u = 320 - 460 * 0.725
  // * (1 + k1 0.725^2) ~ -5 (k1 = -0.05): a little less than half the disc is in the image.
  std::mt19937_64 rng(3);
  const RenderedFrame cut =
      render_frame(cam, single_led({0, 1.45, 3}, 1000.0, 0.9999), standing_at({0, 0, 1}), 0.0, opt, rng, {});
  REQUIRE(cut.leds.size() == 1);
  const RenderedLed& l = cut.leds[0];
  CHECK_FALSE(l.fully_inside);
  CHECK(std::abs(l.uv.x()) < l.radius_px);
  // Off axis (theta ~ 36 deg) the level is ~ peak cos^4(theta) ~ 100 DN; it reaches the edge.
  CHECK(static_cast<int>(cut.gray.at<uchar>(static_cast<int>(std::lround(l.uv.y())), 0)) > 80);
  const double full = std::numbers::pi * l.radius_px * l.radius_px;
  const double bright = cv::countNonZero(cut.gray > 50);
  CHECK(bright > 0.3 * full);
  CHECK(bright < 0.7 * full);

  const RenderedFrame gone =
      render_frame(cam, single_led({0, 2.5, 3}, 1000.0, 0.9999), standing_at({0, 0, 1}), 0.0, opt, rng, {});
  CHECK(gone.leds.empty());
  CHECK(cv::countNonZero(gone.gray > 10) == 0);
}

TEST_CASE("Blackout: no pixel above the noise, no LED in the ground truth", "[sim]") {
  const Scenario sc = make_scenario("static");
  RenderOptions opt;
  const PoseAt pose = [&sc](double t) { return sc.trajectory->state(t).T_BtoW(); };
  std::mt19937_64 rng(4);
  const RenderedFrame lit = render_frame(sc.camera, sc.map, pose, 1.0, opt, rng, {});
  CHECK(lit.leds.size() == 2);
  double mx = 0;
  cv::minMaxLoc(lit.gray, nullptr, &mx);
  CHECK(mx > 120);
  opt.lights_on = false;
  const RenderedFrame dark = render_frame(sc.camera, sc.map, pose, 1.0, opt, rng, {});
  CHECK(dark.leds.empty());
  cv::minMaxLoc(dark.gray, nullptr, &mx);
  CHECK(mx <= opt.black_dn + 6.0 * opt.read_noise_dn);
  // The dark frame's noise is the read noise (plus quantisation) around the black level.
  cv::Scalar mean, sd;
  cv::meanStdDev(dark.gray, mean, sd);
  CHECK(mean[0] == Approx(opt.black_dn).margin(0.02));
  CHECK(sd[0] == Approx(std::sqrt(opt.read_noise_dn * opt.read_noise_dn + 1.0 / 12.0)).epsilon(0.03));
}

TEST_CASE("Ground truth of a walking frame matches the image, same seed -> same pixels", "[sim]") {
  SimOptions so;
  so.seed = 9;
  const Simulator sim(make_scenario("walk"), so);
  int checked = 0;
  for (std::size_t k : {60u, 300u, 420u, 555u, 900u, 1400u, 2000u}) {
    const RenderedFrame fr = sim.render(k);
    const cv::Mat again = sim.render(k).gray;
    CHECK(cv::countNonZero(fr.gray != again) == 0);
    // Every bright pixel belongs to a ground-truth LED disc, and every LED shows bright pixels.
    cv::Mat covered(fr.gray.size(), CV_8U, cv::Scalar(0));
    for (const RenderedLed& l : fr.leds) {
      cv::circle(covered, cv::Point(static_cast<int>(std::lround(l.uv.x())), static_cast<int>(std::lround(l.uv.y()))),
                 static_cast<int>(std::ceil(l.radius_px * 1.25 + 4)), cv::Scalar(255), cv::FILLED);
      cv::Mat disc(fr.gray.size(), CV_8U, cv::Scalar(0));
      cv::circle(disc, cv::Point(static_cast<int>(std::lround(l.uv.x())), static_cast<int>(std::lround(l.uv.y()))),
                 static_cast<int>(std::floor(l.radius_px * 0.8)), cv::Scalar(255), cv::FILLED);
      double mx = 0;
      cv::minMaxLoc(fr.gray, nullptr, &mx, nullptr, nullptr, disc);
      INFO("frame " << k << " LED " << l.id);
      CHECK(mx > 60);
      CHECK(l.t_center_s == Approx(sim.frame_time_s(k) + l.uv.y() * sim.scenario().camera.row_time_s).margin(1e-12));
      ++checked;
    }
    CHECK(cv::countNonZero((fr.gray > 30) & (covered == 0)) == 0);
  }
  CHECK(checked >= 7);
  SimOptions other = so;
  other.seed = 10;
  CHECK(cv::countNonZero(Simulator(make_scenario("walk"), other).render(300).gray != sim.render(300).gray) > 1000);
}

TEST_CASE("Rolling shutter: a camera moving along its rows squeezes the blob by 1/(1 + rate * row_time)", "[sim]") {
  CameraModel cam = default_sim_camera();
  cam.dist = {0, 0, 0, 0, 0};
  const double speed = 20.0;  // m/s along body x = camera +y (rows), to make the effect large
  const PoseAt moving = [speed](double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(speed * (t - 0.0072), 0.0, 1.0);  // above the LED at row ~240
    return T;
  };
  std::mt19937_64 rng(6);
  const RenderedFrame fr = render_frame(cam, single_led({0, 0, 3}, 1000.0, 0.9999), moving, 0.0, noise_free(), rng, {});
  REQUIRE(fr.leds.size() == 1);
  // Image motion c = f v / Z px/s; rows r = p0 - c r row_time: heights scale by 1 / (1 + c row_time).
  const double c = cam.fy * speed / 2.0;
  const double expected = 46.0 / (1.0 + c * cam.row_time_s);
  CHECK(fr.leds[0].row_max - fr.leds[0].row_min == Approx(expected).margin(0.3));
  CHECK(fr.leds[0].uv.y() == Approx(240.0).margin(1.0));
  // The image agrees: bright rows span the squeezed height, not the static 46.
  int first = -1, last = -1;
  for (int y = 0; y < fr.gray.rows; ++y)
    if (fr.gray.at<uchar>(y, 320) > 120) {
      if (first < 0) first = y;
      last = y;
    }
  CHECK(last - first + 1 == Approx(expected).margin(1.5));
}
