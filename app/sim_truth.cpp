#include "app/sim_truth.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <opencv2/core/persistence.hpp>

#include "core/common/csv_reader.hpp"
#include "core/common/input_error.hpp"

namespace luxloc::app {

namespace fs = std::filesystem;

bool SimTruth::at(double t, Eigen::Matrix3d& R, Eigen::Vector3d& p) const {
  if (rows.size() < 2 || t < rows.front().t || t > rows.back().t) return false;
  auto it = std::lower_bound(rows.begin(), rows.end(), t, [](const SimTruthRow& a, double x) { return a.t < x; });
  const std::size_t i = std::min<std::size_t>(it == rows.begin() ? 0 : static_cast<std::size_t>(it - rows.begin()) - 1,
                                              rows.size() - 2);
  const SimTruthRow &a = rows[i], &b = rows[i + 1];
  const double w = b.t > a.t ? std::clamp((t - a.t) / (b.t - a.t), 0.0, 1.0) : 0.0;
  p = a.p + w * (b.p - a.p);
  const double yaw = a.yaw + w * std::remainder(b.yaw - a.yaw, 2 * std::numbers::pi);
  const double roll = a.roll + w * (b.roll - a.roll), pitch = a.pitch + w * (b.pitch - a.pitch);
  R = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  return true;
}

SimTruth read_truth(const fs::path& path) {
  CsvReader r(path.string());
  const int ct = r.require_column("t"), cx = r.require_column("x"), cy = r.require_column("y");
  const int cz = r.column("z"), cyaw = r.column("yaw"), croll = r.column("roll"), cpitch = r.column("pitch");
  SimTruth truth;
  truth.has_tilt = croll >= 0 && cpitch >= 0 && cyaw >= 0;
  truth.has_z = cz >= 0;
  while (r.next_row()) {
    SimTruthRow row;
    row.t = r.number(ct);
    row.p = {r.number(cx), r.number(cy), cz >= 0 ? r.number(cz) : 0.0};
    if (cyaw >= 0) row.yaw = r.number(cyaw);
    if (truth.has_tilt) {
      row.roll = r.number(croll);
      row.pitch = r.number(cpitch);
    }
    if (!truth.rows.empty() && !(row.t > truth.rows.back().t)) continue;  // out of order: skipped
    truth.rows.push_back(row);
  }
  return truth;
}

std::vector<std::pair<double, double>> read_blackouts(const fs::path& sim_truth) {
  std::vector<std::pair<double, double>> out;
  if (!fs::exists(sim_truth)) return out;
  try {
    cv::FileStorage fs(sim_truth.string(), cv::FileStorage::READ);
    for (const cv::FileNode& b : fs["blackouts"])
      out.emplace_back(static_cast<double>(b["start_s"]), static_cast<double>(b["duration_s"]));
  } catch (const cv::Exception&) {
    throw InputError(sim_truth.string(), 0, "blackouts", "not a readable OpenCV YAML file");
  }
  return out;
}

std::vector<TrueLedBlob> true_led_blobs(const SimTruth& truth, const CameraModel& camera, const LedMap& map, double t,
                                        const sim::RenderOptions& options, std::mt19937_64& rng) {
  const sim::PoseAt pose_at = [&](double ts) {
    Eigen::Matrix3d R;
    Eigen::Vector3d p;
    if (!truth.at(std::clamp(ts, truth.rows.front().t, truth.rows.back().t), R, p)) R.setIdentity();
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R;
    T.translation() = p;
    return T;
  };
  std::vector<TrueLedBlob> out;
  const sim::RenderedFrame rf = sim::render_frame(camera, map, pose_at, t, options, rng);
  for (const sim::RenderedLed& l : rf.leds) {
    const Led* led = map.find_id(l.id);
    const int klass = led ? map.class_of(static_cast<std::size_t>(led - map.leds().data())) : -1;
    out.push_back({l.id, l.uv, l.radius_px, l.row_max - l.row_min, l.fully_inside, klass});
  }
  return out;
}

}  // namespace luxloc::app
