#include "core/sim/uwb_synth.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include "core/sim/seeding.hpp"

namespace luxloc::sim {

std::vector<UwbAnchorBias> draw_uwb_biases(const std::vector<UwbAnchor>& anchors, const UwbSimOptions& o,
                                           std::uint64_t seed) {
  std::vector<UwbAnchorBias> out;
  const bool biased = o.bias_max_m > o.bias_min_m, scaled = o.scale_sigma > 0.0;
  if (!biased && !scaled) return out;
  std::mt19937_64 rng = make_rng(seed, RandomStream::uwb_bias);
  std::uniform_real_distribution<double> u(o.bias_min_m, o.bias_max_m);
  for (const UwbAnchor& a : anchors) out.push_back({a.id, biased ? u(rng) : 0.0, 1.0});
  // The scales after every bias: a session drawn before scales existed keeps its biases.
  std::normal_distribution<double> n(0.0, 1.0);
  if (scaled)
    for (UwbAnchorBias& b : out) b.scale = 1.0 + o.scale_sigma * n(rng);
  return out;
}

std::vector<SimUwbMeasurement> synthesize_uwb(const Trajectory& trajectory, const std::vector<UwbAnchor>& anchors,
                                              const UwbSimOptions& o, double duration_s, std::uint64_t seed) {
  std::vector<SimUwbMeasurement> out;
  if (anchors.empty() || !(o.rate_hz > 0.0)) return out;
  std::mt19937_64 rng = make_rng(seed, RandomStream::uwb);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::exponential_distribution<double> bias(1.0 / o.nlos_bias_mean_m);
  const std::vector<UwbAnchorBias> offsets = draw_uwb_biases(anchors, o, seed);
  const double n_anchors = static_cast<double>(anchors.size());
  for (std::size_t k = 0;; ++k) {
    const double t = o.offset_s + static_cast<double>(k) / o.rate_hz;
    if (t >= duration_s) break;
    for (std::size_t i = 0; i < anchors.size(); ++i) {
      const UwbAnchor& a = anchors[i];
      const double t_i = o.stagger ? t + static_cast<double>(i) / (n_anchors * o.rate_hz) : t;
      if (t_i >= duration_s) break;
      const BodyState s = trajectory.state(t_i);
      const Eigen::Vector3d d = s.p_BinW - a.p_inW;
      SimUwbMeasurement m;
      m.true_range_m = d.norm();
      // Draw every variable each time, whatever the branch: the stream stays aligned.
      const double n_r = normal(rng), n_a = normal(rng), u = unit(rng), b = bias(rng), n_nlos = normal(rng);
      const bool blocked = a.id == o.blocked_anchor && t_i >= o.blocked_from_s && t_i < o.blocked_to_s;
      m.nlos = u < o.nlos_probability || blocked;
      m.sample.t = seconds_to_ns(t_i);
      m.sample.anchor = a.id;
      const double offset = offsets.empty() ? 0.0 : offsets[i].bias_m;
      const double scale = offsets.empty() ? 1.0 : offsets[i].scale;
      m.sample.range_m = std::max(0.0, scale * m.true_range_m + offset + o.range_sigma_m * n_r +
                                           (m.nlos ? o.nlos_bias_min_m + b : 0.0));
      if (o.with_aoa) {
        const double theta = std::atan2(d.y(), d.x()) + o.aoa_sigma_rad * n_a +
                             (m.nlos ? o.nlos_aoa_sigma_rad * n_nlos : 0.0);
        m.sample.aoa_rad = std::remainder(theta, 2.0 * std::numbers::pi);
      }
      out.push_back(m);
    }
  }
  return out;
}

}  // namespace luxloc::sim
