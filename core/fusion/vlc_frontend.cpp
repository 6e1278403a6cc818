#include "core/fusion/vlc_frontend.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/vlc/stripe_decoder.hpp"

namespace luxloc {

struct DecodedFrame::Impl {
  std::vector<LedObservation> accepted;  // identified LEDs only
};

const std::vector<LedObservation>& accepted_leds(const DecodedFrame& frame) {
  static const std::vector<LedObservation> none;
  return frame.impl ? frame.impl->accepted : none;
}

struct VlcFrontend::State {
  State(const CameraModel& c, const LedMap& m, const FusionOptions& o, double h)
      : camera(c), shared_map(std::make_shared<const LedMap>(m)), map(*shared_map), index(map), options(o),
        device_height_m(h), decoder(c, shared_map) {}
  CameraModel camera;
  std::shared_ptr<const LedMap> shared_map;  // one copy for the decoder and the fusion
  const LedMap& map;                         // *shared_map
  LedClassIndex index;  // of `map` (declared after it)
  FusionOptions options;
  double device_height_m;
  StripeDecoder decoder;
};

VlcFrontend::VlcFrontend(const CameraModel& camera, const LedMap& map, const FusionOptions& options,
                         double device_height_m)
    : state_(std::make_unique<State>(camera, map, options, device_height_m)) {}

VlcFrontend::~VlcFrontend() = default;

DecodedFrame VlcFrontend::decode(const FrameSample& frame) const {
  DecodedFrame f;
  f.t_frame = f.t_obs = frame.t;
  auto impl = std::make_shared<DecodedFrame::Impl>();
  double rows = 0.0;
  for (LedObservation& o : state_->decoder.decode(frame.gray)) {
    if (!o.classified()) {
      ++f.rejected;
      continue;
    }
    // A blob cut by the border has a biased centre: it identifies an LED but is not
    // used to position.
    if (o.touches_border) continue;
    rows += o.uv.y();
    impl->accepted.push_back(std::move(o));
  }
  f.leds = static_cast<int>(impl->accepted.size());
  if (f.leds > 0) {
    // Rolling shutter: the LEDs were exposed when their rows were read, mid-exposure.
    const CameraModel& c = state_->camera;
    f.t_obs = frame.t + seconds_to_ns(c.row_offset_s(rows / f.leds) + 0.5 * c.exposure_s);
  }
  f.impl = std::move(impl);
  return f;
}

DecodedFrame VlcFrontend::derotated(const DecodedFrame& frame, const Eigen::Vector3d& omega_inB) const {
  if (!frame.impl || frame.leds == 0 || !omega_inB.allFinite() || omega_inB.norm() == 0.0) return frame;
  const CameraModel& c = state_->camera;
  auto impl = std::make_shared<DecodedFrame::Impl>(*frame.impl);
  const double w = omega_inB.norm();
  const Eigen::Vector3d axis = omega_inB / w;
  for (LedObservation& o : impl->accepted) {
    const double t_i = c.row_offset_s(o.uv.y()) + 0.5 * c.exposure_s;  // after t_frame, as decode()'s t_obs
    const double dt = t_i - ns_to_seconds(frame.t_obs - frame.t_frame);
    // World ray R(t_i) r_B = R(t_obs) Exp(omega dt) r_B: at t_obs the body sees Exp(omega dt) r_B.
    const Eigen::Vector3d r_B = c.R_CtoB * c.bearing(o.uv);
    const Eigen::Vector3d r_C = c.R_CtoB.transpose() * (Eigen::AngleAxisd(w * dt, axis) * r_B);
    Eigen::Vector2d uv;
    if (c.project(r_C, uv)) o.uv = uv;
  }
  DecodedFrame out = frame;
  out.impl = std::move(impl);
  return out;
}

ReprojectionLikelihood VlcFrontend::likelihood(const DecodedFrame& frame, const Eigen::Matrix3d& R_BtoW) const {
  const State& s = *state_;
  // Pixel noise plus what the attitude uncertainty does to a bearing: f * sigma_att.
  const double f = 0.5 * (s.camera.fx + s.camera.fy);
  const double sigma_px2 = s.options.vlc_pixel_sigma * s.options.vlc_pixel_sigma +
                           (f * s.options.attitude_sigma_rad) * (f * s.options.attitude_sigma_rad);
  std::vector<ReprojectionTerm> terms;
  // FusionOptions::vlc_frame_correlation: frames whose errors persist count as fewer frames.
  const double k = std::max(1.0, s.options.vlc_frame_correlation);
  const double inv = 1.0 / (sigma_px2 * k * k);
  if (frame.impl)
    for (const LedObservation& o : frame.impl->accepted) {
      if (o.led_index >= 0)
        terms.push_back({s.map.leds()[static_cast<std::size_t>(o.led_index)].p_inW, o.uv, inv, -1});
      else
        terms.push_back({Eigen::Vector3d::Zero(), o.uv, inv, o.freq_class});
    }
  return ReprojectionLikelihood(s.camera, R_BtoW, s.device_height_m, std::move(terms), 5.0 * std::sqrt(sigma_px2),
                                ReuseAssociation{&s.map, &s.index});
}

ReprojectionLikelihood VlcFrontend::resolved_likelihood(const DecodedFrame& frame, const Eigen::Matrix3d& R_BtoW,
                                                        const std::optional<PoseHint>& hint,
                                                        std::size_t* dropped) const {
  const ReprojectionLikelihood lik = likelihood(frame, R_BtoW);
  if (!lik.has_reused()) {
    if (dropped) *dropped = 0;
    return lik;
  }
  if (!hint) return lik.resolved(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0, dropped);  // drops every reused term
  // Too uncertain to tell the copies apart: drop the reused terms (3 sigma inside the
  // smallest capture radius among them, else ambiguous).
  double capture = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < lik.size(); ++i)
    if (lik.term(i).klass >= 0) capture = std::min(capture, state_->index.capture_radius(lik.term(i).klass));
  if (!(3.0 * hint->sigma_m < capture))
    return lik.resolved(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0, dropped);
  return lik.resolved(hint->p_inW.x(), hint->p_inW.y(), hint->yaw_offset_rad, dropped);
}

const LedMap& VlcFrontend::map() const { return state_->map; }
void VlcFrontend::set_device_height_m(double z_m) {
  if (std::isfinite(z_m)) state_->device_height_m = z_m;
}
double VlcFrontend::device_height_m() const { return state_->device_height_m; }

std::vector<CameraHeight> VlcFrontend::heights(const DecodedFrame& frame, const Eigen::Matrix3d& R_BtoW,
                                               double z_hint_m, const CameraHeightOptions& o) const {
  const State& s = *state_;
  std::vector<CameraHeight> out;
  if (!frame.impl) return out;
  // Known LEDs only (a reused frequency's copy is not known before the position is), and
  // no border blobs (their centres and sizes are biased).
  if (std::optional<CameraHeight> h = camera_height(sightings_from(frame.impl->accepted, s.map), s.camera, R_BtoW, z_hint_m, o))
    out.push_back(*h);
  std::optional<CameraHeight> best;
  for (const LedObservation& ob : frame.impl->accepted) {
    // The size only from an envelope fit: a blob's bright-pixel count depends on its stripes.
    if (ob.led_index < 0 || ob.touches_border || !ob.radius_from_envelope ||
        ob.led_index >= static_cast<int>(s.map.size()))
      continue;
    const Led& l = s.map.leds()[static_cast<std::size_t>(ob.led_index)];
    if (!l.diameter_known) continue;
    const std::optional<CameraHeight> d = disc_height(DiscSighting{l.p_inW, ob.uv, ob.radius_px, l.diameter_m}, s.camera, R_BtoW, o);
    if (d && (!best || d->sigma_m < best->sigma_m)) best = d;
  }
  if (best) out.push_back(*best);
  return out;
}
bool VlcFrontend::reuses_frequencies() const { return state_->map.reuses_frequencies(); }

double VlcFrontend::capture_radius(int klass) const { return state_->index.capture_radius(klass); }

std::optional<YawMeasurement> VlcFrontend::yaw_offset(const DecodedFrame& frame, const Eigen::Matrix3d& R_BtoW,
                                                     const std::optional<PoseHint>& hint) const {
  // Each LED's bearing through R_BtoW, met with its height, gives the horizontal vector
  // camera -> LED in R_BtoW's world, h_i = p_Li - p_i (p_i: ReprojectionLikelihood::invert).
  // With the true attitude Rz(e) R_BtoW the map sees Rz(e) h_i, so the LEDs' pattern about
  // its centroid, a_i = p_Li - mean, is the bearings' pattern b_i turned by e: the least-
  // squares turn (2-D Procrustes) is e = atan2(sum b_i x a_i, sum b_i . a_i). A tilt error
  // moves every h_i alike and cancels in b_i.
  const ReprojectionLikelihood lik = resolved_likelihood(frame, R_BtoW, hint);
  std::vector<Eigen::Vector2d> a, b;
  std::vector<double> dz;
  if (!frame.impl) return std::nullopt;
  const State& s = *state_;
  for (std::size_t i = 0; i < lik.size(); ++i) {
    const std::optional<Eigen::Vector2d> p = lik.invert(i);
    if (!p) continue;
    const Eigen::Vector3d& L = lik.term(i).p_LinW;
    a.push_back(L.head<2>());
    b.push_back(L.head<2>() - *p);
    dz.push_back(std::max(0.3, L.z() - s.device_height_m));
  }
  if (a.size() < 2) return std::nullopt;
  Eigen::Vector2d ca = Eigen::Vector2d::Zero(), cb = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < a.size(); ++i) {
    ca += a[i];
    cb += b[i];
  }
  ca /= static_cast<double>(a.size());
  cb /= static_cast<double>(b.size());
  double cross = 0.0, dot = 0.0, spread2 = 0.0, dz2 = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector2d ai = a[i] - ca, bi = b[i] - cb;
    cross += bi.x() * ai.y() - bi.y() * ai.x();
    dot += bi.dot(ai);
    spread2 += ai.squaredNorm();
    dz2 += dz[i] * dz[i];
  }
  // Sigma: each h_i is off by dz sigma_px / f (pixel noise) horizontally; a turn of the
  // pattern is that over its spread. 0.3 m: a shorter baseline says little.
  if (spread2 < 0.09 || dot <= 0.0) return std::nullopt;
  const double f = 0.5 * (s.camera.fx + s.camera.fy);
  const double sigma_h = std::sqrt(dz2 / static_cast<double>(a.size())) * s.options.vlc_pixel_sigma / f;
  YawMeasurement m;
  m.t = frame.t_obs;
  m.offset_rad = std::atan2(cross, dot);
  // Floor 0.005 rad (0.3 deg): the map survey (~1 cm over a few metres) and the lens model.
  m.sigma_rad = std::hypot(sigma_h / std::sqrt(spread2), 0.005);
  return m;
}

std::optional<PositionMeasurement> VlcFrontend::fix(const DecodedFrame& frame, const Eigen::Matrix3d& R_BtoW,
                                                   const std::optional<PoseHint>& hint) const {
  // Each LED's bearing, intersected with its height, places the body; the mean of those.
  const ReprojectionLikelihood lik = resolved_likelihood(frame, R_BtoW, hint);
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int n = 0;
  for (std::size_t i = 0; i < lik.size(); ++i)
    if (auto p = lik.invert(i)) {
      sum += *p;
      ++n;
    }
  if (n == 0) return std::nullopt;
  PositionMeasurement m;
  m.t = frame.t_obs;
  m.z = sum / n;
  const State& s = *state_;
  const double dz = 2.0;  // typical ceiling distance for the spread of one bearing fix
  const double sigma = dz * (s.options.vlc_pixel_sigma / s.camera.fx + s.options.attitude_sigma_rad) + 0.01;
  m.R = Eigen::Matrix2d::Identity() * sigma * sigma / n;
  return m;
}

}  // namespace luxloc
