#include "core/sim/uwb_synth.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include "core/sim/seeding.hpp"

namespace luxloc::sim {

std::vector<SimUwbMeasurement> synthesize_uwb(const Trajectory& trajectory, const std::vector<UwbAnchor>& anchors,
                                              const UwbSimOptions& o, double duration_s, std::uint64_t seed) {
  std::vector<SimUwbMeasurement> out;
  if (anchors.empty() || !(o.rate_hz > 0.0)) return out;
  std::mt19937_64 rng = make_rng(seed, RandomStream::uwb);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::exponential_distribution<double> bias(1.0 / o.nlos_bias_mean_m);
  for (std::size_t k = 0;; ++k) {
    const double t = o.offset_s + static_cast<double>(k) / o.rate_hz;
    if (t >= duration_s) break;
    const BodyState s = trajectory.state(t);
    for (const UwbAnchor& a : anchors) {
      const Eigen::Vector3d d = s.p_BinW - a.p_inW;
      SimUwbMeasurement m;
      m.true_range_m = d.norm();
      // Draw every variable each time, whatever the branch: the stream stays aligned.
      const double n_r = normal(rng), n_a = normal(rng), u = unit(rng), b = bias(rng), n_nlos = normal(rng);
      m.nlos = u < o.nlos_probability;
      m.sample.t = seconds_to_ns(t);
      m.sample.anchor = a.id;
      m.sample.range_m = std::max(0.0, m.true_range_m + o.range_sigma_m * n_r +
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
