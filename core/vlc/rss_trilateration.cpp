#include "core/vlc/rss_trilateration.hpp"

#include <Eigen/Dense>
#include <algorithm>

namespace luxloc {

double rss_distance(double C, double power_t, double h, double received) {
  if (!(C > 0) || !(power_t > 0) || !(h > 0) || !(received > 0) || !std::isfinite(C * power_t * h * received))
    return std::numeric_limits<double>::quiet_NaN();
  return std::pow(C * power_t * h * h / received, 0.25);  // SEEDS A S201 (corrected)
}

double rss_horizontal_distance(double d, double h) {
  if (!std::isfinite(d) || !std::isfinite(h)) return std::numeric_limits<double>::quiet_NaN();
  return std::sqrt(std::max(0.0, d * d - h * h));
}

std::vector<RssMeasurement> rss_measurements_from(const std::vector<LedObservation>& observations, const LedMap& map,
                                                  const RssOptions& options) {
  std::vector<RssMeasurement> out;
  for (const LedObservation& o : observations) {
    if (!o.accepted() || o.led_index >= static_cast<int>(map.size())) continue;
    if ((o.saturated && !options.use_saturated) || (o.touches_border && !options.use_border_blobs)) continue;
    const Led& l = map.leds()[static_cast<std::size_t>(o.led_index)];
    out.push_back({l.p_inW, l.power, o.received_power()});
  }
  return out;
}

namespace {

struct Usable {
  Eigen::Vector2d xy;
  double h, log_pt_h2, log_pr;
};

}  // namespace

VlcFix rss_fix(const std::vector<RssMeasurement>& leds, double z_receiver, const RssOptions& o,
               const Eigen::Matrix3d& R_BtoW, const Eigen::Vector3d& p_CinB) {
  VlcFix fix;
  fix.method = VlcFix::Method::Rss;
  fix.R_BtoW = R_BtoW;
  if (!std::isfinite(z_receiver) || !R_BtoW.allFinite() || !p_CinB.allFinite()) return fix;
  std::vector<Usable> u;
  for (const RssMeasurement& m : leds) {
    const double h = m.p_LinW.z() - z_receiver;
    if (!m.p_LinW.allFinite() || !(h > 0) || !(m.received > 0) || !(m.power_t > 0) || !std::isfinite(m.received))
      continue;
    u.push_back({m.p_LinW.head<2>(), h, std::log(m.power_t * h * h), std::log(m.received)});
  }
  fix.n_leds = static_cast<int>(u.size());
  const bool known_C = o.C > 0 && std::isfinite(o.C);
  const std::size_t n = u.size();
  if (n < (known_C ? 3u : 4u)) return fix;
  // Collinear LEDs leave a mirror ambiguity: no fix.
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const Usable& m : u) c += m.xy;
  c /= static_cast<double>(n);
  Eigen::Matrix2d S = Eigen::Matrix2d::Zero();
  for (const Usable& m : u) S += (m.xy - c) * (m.xy - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(S);
  if (!(es.eigenvalues()(0) > 1e-4 * std::max(es.eigenvalues()(1), 1e-12))) return fix;

  // Start. C known: S203's circles, linearised by subtracting the first. C unknown: the
  // centroid weighted by 1/d^2 ~ sqrt(P_r / (P_t h^2)), which needs no C.
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  if (known_C) {
    std::vector<double> r2(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double d = std::pow(o.C * std::exp(u[i].log_pt_h2 - u[i].log_pr), 0.25);
      const double r = rss_horizontal_distance(d, u[i].h);
      r2[i] = r * r;
    }
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    Eigen::Vector2d b = Eigen::Vector2d::Zero();
    for (std::size_t i = 1; i < n; ++i) {
      const Eigen::Vector2d a = 2.0 * (u[i].xy - u[0].xy);
      const double rhs = r2[0] - r2[i] + u[i].xy.squaredNorm() - u[0].xy.squaredNorm();
      A += a * a.transpose();
      b += a * rhs;
    }
    p = A.ldlt().solve(b);
    if (!p.allFinite()) p = c;
  } else {
    double wsum = 0;
    for (const Usable& m : u) {
      const double w = std::exp(0.5 * (m.log_pr - m.log_pt_h2));
      p += w * m.xy;
      wsum += w;
    }
    p = wsum > 0 ? Eigen::Vector2d(p / wsum) : c;
  }

  // Levenberg-Marquardt on e_i = log P_r - (log C + log(P_t h^2) - 2 log(r^2 + h^2)).
  const int k = known_C ? 2 : 3;
  Eigen::Vector3d th(p.x(), p.y(), known_C ? std::log(o.C) : 0.0);
  auto residuals = [&](const Eigen::Vector3d& t, Eigen::VectorXd& e, Eigen::MatrixXd* J) {
    e.resize(static_cast<Eigen::Index>(n));
    if (J) J->resize(static_cast<Eigen::Index>(n), k);
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d dxy = t.head<2>() - u[i].xy;
      const double D = dxy.squaredNorm() + u[i].h * u[i].h;
      const auto ii = static_cast<Eigen::Index>(i);
      e(ii) = u[i].log_pr - (t.z() + u[i].log_pt_h2 - 2.0 * std::log(D));
      if (J) {
        (*J)(ii, 0) = -4.0 * dxy.x() / D;  // d(model)/dx
        (*J)(ii, 1) = -4.0 * dxy.y() / D;
        if (k == 3) (*J)(ii, 2) = 1.0;
      }
    }
  };
  if (!known_C) {  // best log C at the start
    Eigen::VectorXd e;
    residuals(th, e, nullptr);
    th.z() = e.mean();
  }
  Eigen::VectorXd e;
  Eigen::MatrixXd J;
  residuals(th, e, &J);
  double cost = e.squaredNorm(), lambda = 1e-3;
  for (int it = 0; it < o.max_iterations; ++it) {
    const Eigen::MatrixXd H = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * e;  // model increases by J d: e decreases
    Eigen::MatrixXd Hd = H;
    Hd.diagonal() += lambda * H.diagonal().cwiseMax(1e-9);
    const Eigen::VectorXd step = Hd.ldlt().solve(g);
    if (!step.allFinite()) break;
    Eigen::Vector3d cand = th;
    for (int j = 0; j < k; ++j) cand(j) += step(j);
    Eigen::VectorXd ec;
    residuals(cand, ec, nullptr);
    const double cc = ec.squaredNorm();
    if (cc < cost) {
      th = cand;
      cost = cc;
      residuals(th, e, &J);
      lambda = std::max(lambda * 0.3, 1e-9);
      if (step.norm() < 1e-10) break;
    } else {
      lambda *= 10.0;
      if (lambda > 1e8) break;
    }
  }
  const Eigen::MatrixXd H = J.transpose() * J;
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(H);
  if (!th.allFinite() || !lu.isInvertible()) return fix;
  const Eigen::MatrixXd cov = o.power_rel_sigma * o.power_rel_sigma * lu.inverse();
  if (!cov.allFinite()) return fix;
  const Eigen::Vector3d p_CinW(th.x(), th.y(), z_receiver);
  fix.p_BinW = p_CinW - R_BtoW * p_CinB;
  fix.cov_xy = cov.topLeftCorner(2, 2);
  fix.residual_px = std::sqrt(cost / static_cast<double>(n));
  fix.valid = fix.p_BinW.allFinite();
  return fix;
}

RssCalibration calibrate_rss_constant(const std::vector<RssSample>& samples) {
  RssCalibration cal;
  std::vector<double> logc;
  std::vector<const RssSample*> used;
  for (const RssSample& s : samples) {
    const Eigen::Vector3d v = s.led.p_LinW - s.p_receiver;
    const double h = v.z(), d = v.norm();
    if (!v.allFinite() || !(h > 0) || !(s.led.received > 0) || !(s.led.power_t > 0)) continue;
    // P_r = C P_t h^2 / d^4  =>  log C = log P_r - log(P_t h^2) + 4 log d  (least squares in log).
    logc.push_back(std::log(s.led.received) - std::log(s.led.power_t * h * h) + 4.0 * std::log(d));
    used.push_back(&s);
  }
  cal.samples = static_cast<int>(logc.size());
  if (logc.empty()) return cal;
  double mean = 0;
  for (double l : logc) mean += l;
  mean /= static_cast<double>(logc.size());
  cal.C = std::exp(mean);
  double ss = 0, sr = 0;
  for (std::size_t i = 0; i < logc.size(); ++i) {
    ss += (logc[i] - mean) * (logc[i] - mean);
    const RssSample& s = *used[i];
    const Eigen::Vector3d v = s.led.p_LinW - s.p_receiver;
    const double d_est = rss_distance(cal.C, s.led.power_t, v.z(), s.led.received);
    sr += (d_est - v.norm()) * (d_est - v.norm());
  }
  cal.rms_log_residual = std::sqrt(ss / static_cast<double>(logc.size()));
  cal.rms_range_error_m = std::sqrt(sr / static_cast<double>(logc.size()));
  cal.valid = std::isfinite(cal.C) && cal.C > 0;
  return cal;
}

}  // namespace luxloc
