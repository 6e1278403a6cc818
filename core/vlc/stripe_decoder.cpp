#include "core/vlc/stripe_decoder.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/vlc/blob_segmenter.hpp"
#include "core/vlc/chord_ellipse.hpp"
#include "core/vlc/frame_levels.hpp"

namespace luxloc {
namespace {

// Per-thread buffers reused from frame to frame: no per-frame heap churn once warm.
struct Scratch {
  cv::Mat gray8, foreign;
  BlobSegmenter segmenter;
  struct RowEdges {
    int v;
    double left, right;
    bool left_ok, right_ok, extent_ok;
  };
  std::vector<RowEdges> rows;
  std::vector<Eigen::Vector2d> edge_pts;
  std::vector<double> rowmax, residuals, value, raw, weight, envelope, runmax, chord_len;
  std::vector<int> colcount;
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

// Pixel source for one blob: bright pixels of other blobs read as background.
class BlobPixels {
 public:
  BlobPixels(const cv::Mat& gray, const cv::Mat& foreign, const cv::Rect& roi, double bg)
      : data_(gray.data), step_(gray.step[0]), foreign_(foreign.empty() ? nullptr : &foreign), roi_(roi), bg_(bg) {}
  double at(int r, int u) const {
    if (foreign_ && r >= roi_.y && r < roi_.y + roi_.height && u >= roi_.x && u < roi_.x + roi_.width &&
        foreign_->ptr<uchar>(r - roi_.y)[u - roi_.x])
      return bg_;
    return data_[static_cast<std::size_t>(r) * step_ + static_cast<std::size_t>(u)];
  }

 private:
  const uchar* data_;
  std::size_t step_;
  const cv::Mat* foreign_;
  cv::Rect roi_;
  double bg_;
};

// Sub-pixel position where the row crosses `level` between pixel u_out (below) and u_in.
double crossing(double val_out, double val_in, int u_out, int u_in, double level) {
  const double den = val_in - val_out;
  const double t = den > 1e-9 ? std::clamp((level - val_out) / den, 0.0, 1.0) : 1.0;
  return u_out + t * (u_in - u_out);
}

double clamp01(double x) { return std::clamp(x, 0.0, 1.0); }

// Mean of the profile over the longest whole number of periods centred in its rows with
// data (fractional rows at the window's ends); 0 when it spans less than one period.
double whole_period_mean(const std::vector<double>& y, const std::vector<double>& w, double period) {
  int a = 0, b = static_cast<int>(y.size()) - 1;
  while (a <= b && w[static_cast<std::size_t>(a)] <= 0) ++a;
  while (b >= a && w[static_cast<std::size_t>(b)] <= 0) --b;
  const double len = b - a + 1;
  if (!(period > 0) || len < period) return 0.0;
  const double span = std::floor(len / period) * period;
  const double lo = a - 0.5 + 0.5 * (len - span), hi = lo + span;  // row i covers [i - 0.5, i + 0.5]
  double s = 0, ws = 0;
  for (int i = a; i <= b; ++i) {
    const double f = std::clamp(std::min(i + 0.5, hi) - std::max(i - 0.5, lo), 0.0, 1.0);
    if (f <= 0 || w[static_cast<std::size_t>(i)] <= 0) continue;
    s += f * y[static_cast<std::size_t>(i)];
    ws += f;
  }
  return ws > 0 ? s / ws : 0.0;
}

}  // namespace

StripeDecoder::StripeDecoder(const CameraModel& camera, const LedMap& map, StripeDecoderOptions options)
    : StripeDecoder(camera, std::make_shared<const LedMap>(map), options) {}

StripeDecoder::StripeDecoder(const CameraModel& camera, std::shared_ptr<const LedMap> map, StripeDecoderOptions options)
    : camera_(camera), map_(map ? std::move(map) : std::make_shared<const LedMap>()), options_(options) {
  double f_lo = options_.min_freq_hz, f_hi = options_.max_freq_hz;
  double max_dark = 0.5;  // off fraction of the longest-period LED
  if (!map_->empty()) {
    f_lo = std::numeric_limits<double>::infinity();
    f_hi = 0.0;
    for (const Led& l : map_->leds()) {
      f_lo = std::min(f_lo, l.freq_hz);
      f_hi = std::max(f_hi, l.freq_hz);
      max_dark = std::max(max_dark, 1.0 - l.duty);
    }
  }
  if (!(f_lo > 0.0) || !(f_hi >= f_lo)) {  // no map and no range given: a wide default
    f_lo = 500.0;
    f_hi = 10000.0;
  }
  const double rt = camera_.row_time_s > 0 ? camera_.row_time_s : 30e-6;
  const double m = std::max(0.0, options_.search_margin);
  max_period_rows_ = (1.0 + m) / (f_lo * rt);
  min_period_rows_ = std::max(2.0, 1.0 / (f_hi * (1.0 + m) * rt));
  if (max_period_rows_ <= min_period_rows_) max_period_rows_ = min_period_rows_ * 2.0;
  // Rows bridged between the stripes of one LED: its longest dark stripe, (1 - duty) of
  // the longest period, plus a margin for the optics blur (SEEDS A S203: one region per LED).
  int k = options_.closing_rows;
  if (k <= 0) k = static_cast<int>(std::ceil(max_dark / (f_lo * rt) + 2.0)) + 1;
  closing_rows_ = std::clamp(k, 3, std::max(3, camera_.height / 3)) | 1;
  if (!map_->empty()) {
    common_duty_ = map_->leds().front().duty;
    for (const Led& l : map_->leds())
      if (std::abs(l.duty - common_duty_) > 1e-6) common_duty_ = 0.0;
  }
  rel_tolerance_ = options_.rel_tolerance;
  if (map_->size() >= 2) rel_tolerance_ = std::min(rel_tolerance_, 0.45 * map_->min_relative_separation());
}

std::vector<LedObservation> StripeDecoder::decode(const cv::Mat& input) const {
  std::vector<LedObservation> out;
  if (input.empty()) return out;
  Scratch& S = scratch();
  const cv::Mat* gp = as_gray8(input, S.gray8);
  if (!gp) return out;  // unsupported pixel format: nothing decodable
  const cv::Mat& gray = *gp;
  const int H = gray.rows, W = gray.cols;
  const StripeDecoderOptions& o = options_;
  const FrameLevels lv = frame_levels(gray, o.min_contrast_dn, o.threshold_sigma);
  const double bg = lv.background, thr = lv.threshold;
  S.segmenter.segment(gray, thr, closing_rows_, o.min_blob_pixels);

  for (const BlobRegion& blob : S.segmenter.blobs()) {
    const int r0 = blob.first_row, r1 = blob.last_row, c0 = blob.first_col, c1 = blob.last_col;
    // Region examined: the bright extent plus one dark stripe above and below, and a
    // quarter of the blob's size around for the soft tails of an unsharp blob.
    const int mc = std::max(3, std::max(c1 - c0 + 1, r1 - r0 + 1) / 4), mr = std::max(closing_rows_ + 3, mc);
    const cv::Rect roi = cv::Rect(c0 - mc, r0 - mr, c1 - c0 + 1 + 2 * mc, r1 - r0 + 1 + 2 * mr) & cv::Rect(0, 0, W, H);
    S.segmenter.mark_foreign(blob, roi, S.foreign);
    const BlobPixels px(gray, S.foreign, roi, bg);
    LedObservation obs;
    // Cut by the border, or maybe: a dark stripe at the top / bottom border can hide the cut.
    obs.touches_border = r0 < closing_rows_ || c0 <= 1 || r1 > H - 1 - closing_rows_ || c1 >= W - 2;

    // --- energy (received power, SEEDS A S201), moments, clipping ---
    const int su0 = std::max(0, c0 - 3), su1 = std::min(W - 1, c1 + 3);
    double energy = 0.0, mom_u = 0.0, mom_v = 0.0, peak = 0.0;
    int n_sat = 0;
    const int ea = std::max(0, r0 - mc), eb = std::min(H - 1, r1 + mc);
    const int eu0 = std::max(0, c0 - mc), eu1 = std::min(W - 1, c1 + mc);
    for (int r = ea; r <= eb; ++r)
      for (int u = eu0; u <= eu1; ++u) {
        const double p = px.at(r, u);
        const double e = p - bg;
        energy += e;
        mom_u += e * u;
        mom_v += e * r;
        if (p > thr) {
          peak = std::max(peak, p);
          if (p >= o.saturation_dn) ++n_sat;
        }
      }
    obs.intensity_sum = energy;
    obs.saturated = n_sat > 0;

    // --- row edges, sub-pixel, on plateau rows ---
    const double peak_amp = peak - bg;
    S.rowmax.assign(static_cast<std::size_t>(r1 - r0 + 1), 0.0);
    for (int r = r0; r <= r1; ++r) {
      double rmax = 0;
      for (int u = su0; u <= su1; ++u) rmax = std::max(rmax, px.at(r, u));
      S.rowmax[static_cast<std::size_t>(r - r0)] = rmax - bg;
    }
    S.rows.clear();
    S.edge_pts.clear();
    for (int r = r0; r <= r1; ++r) {
      const double rmax = S.rowmax[static_cast<std::size_t>(r - r0)];
      if (rmax < o.edge_row_fraction * peak_amp) continue;
      // The first and last bright rows may be cap rows only partly covered by the disc
      // (dimmed by the coverage, not by the stripes): there only a row as bright as its
      // neighbours has its half level at the disc's edge.
      if (r - r0 < 2 || r1 - r < 2) {
        double near = rmax;
        for (int j = std::max(r0, r - 2); j <= std::min(r1, r + 2); ++j)
          near = std::max(near, S.rowmax[static_cast<std::size_t>(j - r0)]);
        if (rmax < o.plateau_fraction * near) continue;
      }
      const double level = bg + o.edge_level * rmax;
      // A row bright up to the border keeps the border as its extent but gives no edge.
      Scratch::RowEdges re{r, 0, 0, false, false, false};
      for (int u = su0; u < su1; ++u)
        if (px.at(r, u) >= level && px.at(r, u + 1) >= level) {
          re.left = re.right = u;
          re.extent_ok = true;
          if (u > 0 && u > su0) {
            re.left = crossing(px.at(r, u - 1), px.at(r, u), u - 1, u, level);
            re.left_ok = true;
          }
          break;
        }
      for (int u = su1; u > su0 && re.extent_ok; --u)
        if (px.at(r, u) >= level && px.at(r, u - 1) >= level) {
          re.right = u;
          if (u < W - 1 && u < su1) {
            re.right = crossing(px.at(r, u + 1), px.at(r, u), u + 1, u, level);
            re.right_ok = true;
          }
          break;
        }
      if (re.left_ok) S.edge_pts.emplace_back(re.left, r);
      if (re.right_ok) S.edge_pts.emplace_back(re.right, r);
      S.rows.push_back(re);
    }

    // --- envelope: ellipse through the chord ends (one trimmed refit), if trustworthy ---
    ChordEllipse el = ChordEllipse::fit(S.edge_pts);
    if (el.ok()) {
      S.residuals.clear();
      for (const auto& p : S.edge_pts) {
        double mid, hw;
        S.residuals.push_back(el.chord(p.y(), mid, hw) ? std::abs(std::abs(p.x() - mid) - hw) : el.radius());
      }
      std::vector<double>& tmp = S.value;  // borrowed, reassigned below
      tmp = S.residuals;
      std::nth_element(tmp.begin(), tmp.begin() + static_cast<long>(tmp.size() / 2), tmp.end());
      const double cut = std::max(0.5, 4.0 * 1.4826 * tmp[tmp.size() / 2]);
      std::size_t kept = 0;
      for (std::size_t i = 0; i < S.edge_pts.size(); ++i)
        if (S.residuals[i] <= cut) S.edge_pts[kept++] = S.edge_pts[i];
      if (kept < S.edge_pts.size()) {
        S.edge_pts.resize(kept);
        el = ChordEllipse::fit(S.edge_pts);
      }
    }
    bool trusted = false;
    if (el.ok()) {
      // Trusted when it fits, is not a thin sliver (a projected disc's axis ratio is the
      // cosine of the viewing angle), is pinned by >= 5 of 12 boundary sectors, and,
      // unless chords with both ends are seen, has its centre in the image; its extent may
      // pass the bright rows by one dark stripe, or more where the border cuts the blob.
      int two_sided = 0;
      double band_top = 1e300, band_bot = -1e300;
      for (const auto& re : S.rows)
        if (re.left_ok && re.right_ok) {
          ++two_sided;
          band_top = std::min(band_top, static_cast<double>(re.v));
          band_bot = std::max(band_bot, static_cast<double>(re.v));
        }
      // One bright stripe across the middle of the disc pins only 4 sectors (the sides,
      // +-25 degrees), yet a sharp fit through it holds: its chords are two-sided and the
      // widest one lies inside the band (the fit interpolates the centre row, and the
      // chord widths' curvature gives the size). Other 4-sector arcs are not trusted.
      const int sectors = el.arc_sectors(S.edge_pts);
      const double rms = el.rms_residual(S.edge_pts);
      const bool pinned = sectors >= 5 || (sectors == 4 && two_sided >= o.min_band_rows && rms <= o.max_band_rms_px &&
                                           el.axis_ratio() >= o.min_band_axis_ratio &&
                                           el.centre().y() >= band_top && el.centre().y() <= band_bot);
      const Eigen::Vector2d& c = el.centre();
      const bool centre_in = c.x() >= 0 && c.x() <= W - 1 && c.y() >= 0 && c.y() <= H - 1;
      const double slack = closing_rows_ + 2.0;
      const bool cut_top = r0 - slack <= 0, cut_bot = r1 + slack >= H - 1;
      const bool cut_left = c0 <= 1, cut_right = c1 >= W - 2;
      trusted = rms <= std::max(o.max_edge_rms_px, 0.05 * el.radius()) && el.axis_ratio() >= o.min_axis_ratio && pinned &&
                (two_sided >= 3 || centre_in) && (cut_top || el.top() >= r0 - slack) &&
                (cut_bot || el.bottom() <= r1 + slack) && (cut_left || c.x() >= c0 - 1) &&
                (cut_right || c.x() <= c1 + 1) && (cut_top || c.y() >= r0 - slack) &&
                (cut_bot || c.y() <= r1 + slack);
    }

    // Two LEDs overlapping in the image make one blob whose edges the trimmed fit may
    // still take for one ellipse: bright pixels well outside it give the merge away.
    // (Not checked at the border, where the ellipse is an extrapolation.)
    bool merged = false;
    if (trusted && !obs.touches_border) {
      int outside = 0;
      const double margin = std::max(2.0, 0.08 * el.radius());
      for (int r = r0; r <= r1; ++r) {
        double mid, hw;
        const bool in = el.chord(r, mid, hw);
        for (int u = su0; u <= su1; ++u)
          if (px.at(r, u) > thr && (!in || std::abs(u - mid) > hw + margin)) ++outside;
      }
      merged = outside > o.max_outside_fraction * blob.bright_pixels;
    }

    // Without a trusted ellipse (soft blob, sliver at the border) the profile uses the core
    // columns: those inside the bright extent of >= 80 % of the plateau rows.
    double core_mid = 0.5 * (c0 + c1), core_hw = 0.5;
    if (!trusted) {
      S.colcount.assign(static_cast<std::size_t>(su1 - su0 + 1), 0);
      for (const auto& re : S.rows) {
        if (!re.extent_ok) continue;
        const int a = std::max(su0, static_cast<int>(std::ceil(re.left)));
        const int b = std::min(su1, static_cast<int>(std::floor(re.right)));
        for (int u = a; u <= b; ++u) ++S.colcount[static_cast<std::size_t>(u - su0)];
      }
      int best = 0;
      for (int i = 0; i < static_cast<int>(S.colcount.size()); ++i)
        if (S.colcount[static_cast<std::size_t>(i)] > S.colcount[static_cast<std::size_t>(best)]) best = i;
      const int need = static_cast<int>(std::ceil(0.8 * S.colcount[static_cast<std::size_t>(best)]));
      int a = best, b = best;
      while (a > 0 && S.colcount[static_cast<std::size_t>(a - 1)] >= need) --a;
      while (b + 1 < static_cast<int>(S.colcount.size()) && S.colcount[static_cast<std::size_t>(b + 1)] >= need) ++b;
      core_mid = su0 + 0.5 * (a + b);
      core_hw = std::max(0.5, 0.5 * (b - a + 1));
    }
    // Rows of the profile. A blob cut by the border keeps only the rows between the first
    // and the last plateau row covering the profile columns: the disc is convex, so the
    // rows between are inside it, those beyond may not be.
    int p0 = r0, p1 = r1;
    if (trusted) {
      p0 = std::max(0, static_cast<int>(std::ceil(el.top())));
      p1 = std::min(H - 1, static_cast<int>(std::floor(el.bottom())));
    } else if (obs.touches_border) {
      const double ka = core_mid - o.profile_chord_fraction * core_hw;
      const double kb = core_mid + o.profile_chord_fraction * core_hw;
      int first = -1, last = -1;
      for (const auto& re : S.rows)
        if (re.extent_ok && re.left <= ka + 0.5 && re.right >= kb - 0.5) {
          if (first < 0) first = re.v;
          last = re.v;
        }
      if (first >= 0) {
        p0 = first;
        p1 = last;
      }
    }

    // --- stripe profile: mean over the central chord of each row (stripes follow sensor
    // rows whatever the blob's orientation) ---
    const int n = std::max(0, p1 - p0 + 1);
    S.value.assign(static_cast<std::size_t>(n), 0.0);
    S.weight.assign(static_cast<std::size_t>(n), 0.0);
    S.chord_len.assign(static_cast<std::size_t>(n), 0.0);
    const double min_hw = trusted ? std::max(0.75, 0.15 * el.max_chord_half_width()) : 0.5;
    int n_rows = 0;
    for (int i = 0; i < n; ++i) {
      const int r = p0 + i;
      double mid = core_mid, hw = core_hw;
      if (trusted && !el.chord(r, mid, hw)) continue;
      if (hw < min_hw) continue;
      const double k = o.profile_chord_fraction * hw;
      int ua = std::max(0, static_cast<int>(std::lround(mid - k)));
      int ub = std::min(W - 1, static_cast<int>(std::lround(mid + k)));
      if (ub < ua) {
        const int um = static_cast<int>(std::lround(mid));
        if (um < 0 || um >= W) continue;
        ua = ub = um;
      }
      double sum = 0;
      for (int u = ua; u <= ub; ++u) sum += px.at(r, u);
      S.value[static_cast<std::size_t>(i)] = sum / (ub - ua + 1) - bg;
      S.weight[static_cast<std::size_t>(i)] = 1.0;
      S.chord_len[static_cast<std::size_t>(i)] = 2.0 * hw;
      ++n_rows;
    }
    // Upper envelope: running max over the longest period, smoothed the same way.
    const int win = std::max(3, static_cast<int>(std::ceil(max_period_rows_)));
    S.runmax.assign(static_cast<std::size_t>(n), 0.0);
    S.envelope.assign(static_cast<std::size_t>(n), 0.0);
    for (int i = 0; i < n; ++i) {
      double mx = 0;
      for (int j = std::max(0, i - win / 2); j <= std::min(n - 1, i + win / 2); ++j)
        if (S.weight[static_cast<std::size_t>(j)] > 0) mx = std::max(mx, S.value[static_cast<std::size_t>(j)]);
      S.runmax[static_cast<std::size_t>(i)] = mx;
    }
    double env_max = 0;
    for (int i = 0; i < n; ++i) {
      double s = 0;
      int cnt = 0;
      for (int j = std::max(0, i - win / 2); j <= std::min(n - 1, i + win / 2); ++j, ++cnt)
        s += S.runmax[static_cast<std::size_t>(j)];
      S.envelope[static_cast<std::size_t>(i)] = cnt ? s / cnt : 0.0;
      env_max = std::max(env_max, S.envelope[static_cast<std::size_t>(i)]);
    }
    // A sharp disc's row means are its on-fractions times one level: the period is
    // estimated on them directly. A soft blob's (no trusted ellipse) are taken as
    // log(row mean + eps): its envelope (Gaussian, vignetting) becomes an additive trend that
    // the fitted polynomial absorbs, and clipped stripes stay periodic. Rows far down the
    // envelope carry no data. The raw row means are kept for the on-fraction below.
    const double eps = std::max(3.0 * lv.noise, 0.03 * env_max);
    double on_num = 0, on_den = 0, chord_sum = 0;
    S.raw.assign(static_cast<std::size_t>(n), 0.0);
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const double env = S.envelope[k];
      if (S.weight[k] <= 0 || !(env > 0.1 * env_max)) {
        S.weight[k] = 0;
        continue;
      }
      S.raw[k] = std::max(0.0, S.value[k]);
      on_num += S.chord_len[k] * S.raw[k];
      on_den += S.chord_len[k] * env;
      chord_sum += S.chord_len[k];
      if (!trusted) S.value[k] = std::log(S.raw[k] + eps);
    }
    // Without an identified LED: the row means over their upper envelope (biased when the
    // exposure is longer than the on-time: no row is then fully on).
    obs.on_fraction = on_den > 0 ? std::clamp(on_num / on_den, 1e-3, 1.0) : 1.0;
    obs.row_span = trusted ? (el.bottom() - el.top()) : static_cast<double>(r1 - r0 + 1);

    const StripePeriodEstimate est =
        n_rows >= o.min_rows ? estimate_stripe_period(S.value, S.weight, min_period_rows_, max_period_rows_, o.period)
                             : StripePeriodEstimate{};
    if (est.valid) {
      obs.period_rows = est.period_rows;
      obs.period_sigma_rows = est.period_sigma_rows;
      obs.freq_hz = 1.0 / (est.period_rows * camera_.row_time_s);
    }

    // --- centre ---
    if (trusted) {
      obs.uv = el.centre();
      obs.radius_px = el.radius();
      obs.radius_from_envelope = true;
      obs.touches_border = el.top() < 0 || el.bottom() > H - 1 || el.centre().x() - el.half_width() < 0 ||
                           el.centre().x() + el.half_width() > W - 1;
    } else {
      // The intensity centroid: under a soft envelope with several stripes the stripes
      // average out; a blob cut by the border is biased (and flagged).
      obs.uv = energy > 0 ? Eigen::Vector2d(mom_u / energy, mom_v / energy)
                          : Eigen::Vector2d(0.5 * (c0 + c1), 0.5 * (r0 + r1));
      obs.radius_px = std::sqrt(blob.bright_pixels / std::numbers::pi / std::max(obs.on_fraction, 0.1));
    }

    // Short blobs: the stripe edges rather than the periodogram (see min_edge_periods).
    bool by_edges = false;
    const double est_periods = est.span_rows * est.cycles_per_row;
    if (est.valid && trusted && common_duty_ > 0 && o.min_edge_periods > 0 &&
        est_periods < std::max(o.min_periods, o.edge_preferred_periods)) {
      const EdgePeriodEstimate ep =
          estimate_period_from_edges(S.value, S.weight, common_duty_, min_period_rows_, max_period_rows_);
      // Under min_periods the edges are the only estimate; between it and
      // edge_preferred_periods they replace the periodogram's when three or more agree.
      if (ep.valid && est.span_rows >= o.min_edge_periods * ep.period_rows &&
          (est_periods < o.min_periods || ep.edges >= 3)) {
        by_edges = true;
        obs.period_rows = ep.period_rows;
        obs.period_sigma_rows = ep.period_sigma_rows;
        obs.freq_hz = 1.0 / (ep.period_rows * camera_.row_time_s);
      }
    }

    // --- decisions: reject rather than guess ---
    const double tol = rel_tolerance_;
    if (c1 - c0 + 1 < o.min_blob_width_px) {
      obs.reject_reason = "too narrow";  // a sliver at the border: its rows are the disc's blurred edge
    } else if (merged) {
      obs.reject_reason = "overlapping blobs";
    } else if (n_rows < o.min_rows) {
      obs.reject_reason = "too few rows";
    } else if (!est.valid || est.explained < o.min_explained) {
      obs.reject_reason = "no stripes";
    } else if (!by_edges && est_periods < o.min_periods) {
      obs.reject_reason = "too few rows";
    } else if (!by_edges && est.peak_to_sidelobe < o.min_peak_to_sidelobe) {
      obs.reject_reason = "ambiguous frequency";
    } else if (map_->empty() || (!by_edges && est.at_range_edge)) {  // at the edge: the true peak lies outside the map's range
      obs.reject_reason = "no map match";
    } else {
      const LedMap::FrequencyMatch mt = map_->match_frequency(obs.freq_hz, tol);
      const double sigma_rel = obs.period_sigma_rows / obs.period_rows;
      if (mt.klass < 0) {
        obs.reject_reason = "no map match";
      } else if (mt.runner_up < o.ambiguity_ratio * mt.rel_error ||
                 sigma_rel > o.max_sigma_fraction * (mt.runner_up - mt.rel_error)) {
        obs.reject_reason = "ambiguous frequency";
      } else {
        obs.freq_class = mt.klass;
        obs.led_index = mt.index;  // -1 for a reused frequency
        obs.led_id = mt.index >= 0 ? map_->leds()[static_cast<std::size_t>(mt.index)].id : -1;
        // Confidence: geometric mean of the periodic fit quality, the closeness of the
        // match and the frequency's certainty, each relative to its acceptance limit.
        const double q_fit = clamp01((est.explained - o.min_explained) / (1.0 - o.min_explained));
        const double q_match = clamp01(1.0 - mt.rel_error / tol);
        const double q_sigma = clamp01(1.0 - sigma_rel / tol);
        obs.confidence = std::cbrt(q_fit * q_match * q_sigma);
        // On-fraction for the RSS power (SEEDS A S201): averaged over whole stripe periods a
        // row's on-fraction is the LED's duty whatever the exposure, so the mean row level
        // there is the always-on level times the duty; the blob's chord-weighted mean over
        // that level is its on-fraction (different from the duty by the partial period).
        const double duty =
            map_->leds()[static_cast<std::size_t>(map_->classes()[static_cast<std::size_t>(mt.klass)].members.front())].duty;
        const double whole = whole_period_mean(S.raw, S.weight, obs.period_rows);
        if (whole > 0 && chord_sum > 0)
          obs.on_fraction = std::clamp(duty * (on_num / chord_sum) / whole, 1e-3, 1.0);
      }
    }
    out.push_back(std::move(obs));
  }
  return out;
}

}  // namespace luxloc
