#pragma once
// Trajectory accuracy (`luxloc eval`, `demo`): each estimated pose is compared with the
// ground truth linearly interpolated at the pose time; horizontal (x, y) error; no
// alignment (both trajectories are in the same world frame, SPEC.md "Frames").
#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "core/eval/trajectory_io.hpp"

namespace luxloc {

struct EvalOptions {
  double coverage_bin_s = 1.0;  // bin width of the coverage measure (kCoverageDefinition)
};

// Printed by `luxloc eval --help` and in reports.
inline constexpr const char* kCoverageDefinition =
    "coverage = share of the ground-truth time span [first, last truth time] lying in "
    "1-s bins (counted from the first truth time; a final partial bin counts by its length) "
    "that hold at least one evaluated pose";

struct PoseError {
  TimeNs t = 0;
  Eigen::Vector2d p_est = Eigen::Vector2d::Zero();
  Eigen::Vector2d p_truth = Eigen::Vector2d::Zero();
  double err_m = 0.0;                                           // |p_est - p_truth| (x, y)
  double yaw_err_rad = std::numeric_limits<double>::quiet_NaN();  // wrapped; NaN: a yaw missing
  // Error against the estimate's own sigma: (ex/sx)^2 + (ey/sy)^2 and |e_yaw| / sigma_yaw;
  // NaN when the pose file has no sigma.
  double mahalanobis2 = std::numeric_limits<double>::quiet_NaN();
  double yaw_z = std::numeric_limits<double>::quiet_NaN();
};

struct EvalResult {
  std::size_t n = 0;          // poses inside the truth span (evaluated)
  std::size_t n_outside = 0;  // poses before the first / after the last truth time (ignored)
  TimeNs truth_t0 = 0, truth_t1 = 0;
  double coverage = 0.0;      // 0..1, see kCoverageDefinition
  double coverage_bin_s = 1.0;
  // Horizontal error statistics, metres; NaN when n == 0.
  double rmse_m = std::numeric_limits<double>::quiet_NaN();
  double mean_m = std::numeric_limits<double>::quiet_NaN();
  double median_m = std::numeric_limits<double>::quiet_NaN();
  double p95_m = std::numeric_limits<double>::quiet_NaN();
  double max_m = std::numeric_limits<double>::quiet_NaN();
  TimeNs t_max = 0;  // time of the largest error
  // Yaw, over poses where both the estimate and the truth have one (angles wrapped).
  std::size_t n_yaw = 0;
  double yaw_rmse_rad = std::numeric_limits<double>::quiet_NaN();
  double yaw_p50_rad = std::numeric_limits<double>::quiet_NaN();  // of |yaw error|
  double yaw_p95_rad = std::numeric_limits<double>::quiet_NaN();
  double yaw_max_rad = std::numeric_limits<double>::quiet_NaN();
  // Honesty of the reported uncertainty (issue 12): the share of poses whose error lies in
  // the estimate's 95 % region, (ex/sx)^2 + (ey/sy)^2 <= 5.99 (chi-square, 2 dof: the
  // 2.45-sigma circle when sx = sy) and |e_yaw| <= 1.96 sigma_yaw; ~0.95 for an honest
  // filter, far less for an overconfident one. NaN without sigma columns.
  std::size_t n_sigma = 0, n_sigma_yaw = 0;
  double consistency = std::numeric_limits<double>::quiet_NaN();
  double yaw_consistency = std::numeric_limits<double>::quiet_NaN();
  double mean_sigma_m = std::numeric_limits<double>::quiet_NaN();  // mean of sqrt((sx^2 + sy^2) / 2)
  // Height (issue 16 part 3): RMSE of z - truth z over every evaluated pose (a planar run's
  // z is its nominal height), and the share within 1.96 sigma_z of those that carry one.
  double z_rmse_m = std::numeric_limits<double>::quiet_NaN();
  std::size_t n_sigma_z = 0;
  double z_consistency = std::numeric_limits<double>::quiet_NaN();
  std::vector<PoseError> errors;  // the evaluated poses, in time order
};

// Settling (issue 14's convergence and kidnap recovery): the time of the first evaluated
// pose after which every error stays below limit_m to the end; NaN when the last pose is
// not below it.
double settle_time_s(const EvalResult& r, double limit_m);

// `truth` must be in strictly increasing time order (read_truth_csv guarantees it; throws
// std::invalid_argument otherwise); `poses` may be in any order.
EvalResult evaluate(const std::vector<TruthRow>& truth, const std::vector<PoseRow>& poses,
                    const EvalOptions& options = {});

// Truth at `t`: linear in x, y, z; yaw along the shorter arc (NaN if either end lacks
// one). False when t lies outside [first, last truth time].
bool interpolate_truth(const std::vector<TruthRow>& truth, TimeNs t, TruthRow& out);
// q-quantile (0..1), linear between order statistics (numpy's default); NaN when empty.
double percentile(std::vector<double> values, double q);
// Angle wrapped to (-pi, pi].
double wrap_angle(double a);

// "ATE RMSE 0.123 m | median 0.101 | p95 0.250 | max 0.400 | n 9000 | coverage 100.0 %"
// (+ " | yaw RMSE 2.3 deg" when yaw was compared).
std::string format_eval_summary(const EvalResult& r);
// Multi-line human report ending with the summary line.
std::string format_eval_report(const EvalResult& r);
// One flat JSON object; unknown values omitted (never NaN).
std::string format_eval_json(const EvalResult& r);

}  // namespace luxloc
