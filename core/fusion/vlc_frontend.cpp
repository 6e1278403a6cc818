#include "core/fusion/vlc_frontend.hpp"

#include <cmath>

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
      : camera(c), map(m), options(o), device_height_m(h), decoder(c, m) {}
  CameraModel camera;
  LedMap map;
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
    if (!o.accepted()) {
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

ReprojectionLikelihood VlcFrontend::likelihood(const DecodedFrame& frame, const Eigen::Matrix3d& R_BtoW) const {
  const State& s = *state_;
  // Pixel noise plus what the attitude uncertainty does to a bearing: f * sigma_att.
  const double f = 0.5 * (s.camera.fx + s.camera.fy);
  const double sigma_px2 = s.options.vlc_pixel_sigma * s.options.vlc_pixel_sigma +
                           (f * s.options.attitude_sigma_rad) * (f * s.options.attitude_sigma_rad);
  std::vector<ReprojectionTerm> terms;
  if (frame.impl)
    for (const LedObservation& o : frame.impl->accepted)
      terms.push_back({s.map.leds()[static_cast<std::size_t>(o.led_index)].p_inW, o.uv, 1.0 / sigma_px2});
  return ReprojectionLikelihood(s.camera, R_BtoW, s.device_height_m, std::move(terms),
                                5.0 * std::sqrt(sigma_px2));
}

std::optional<PositionMeasurement> VlcFrontend::fix(const DecodedFrame& frame, const Eigen::Matrix3d& R_BtoW) const {
  // Each LED's bearing, intersected with its height, places the body; the mean of those.
  const ReprojectionLikelihood lik = likelihood(frame, R_BtoW);
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
