#pragma once
// Known UWB anchor positions by id: from session.yaml / a map file (SPEC.md `anchors`), or
// learnt from the device's own reports (a DWM1001 tag lists each anchor's position).
#include <Eigen/Core>
#include <map>
#include <optional>
#include <vector>

#include "core/common/session_config.hpp"

namespace luxloc {

class UwbAnchorTable {
 public:
  UwbAnchorTable() = default;
  explicit UwbAnchorTable(const std::vector<UwbAnchor>& anchors) {
    for (const UwbAnchor& a : anchors) {
      anchors_[a.id] = a.p_inW;
      if (a.bias_m != 0.0 || a.scale != 1.0) calibrations_[a.id] = a;
    }
  }
  // A measured range with the anchor's calibration (bias_m, scale) removed; as measured
  // for an uncalibrated anchor.
  double corrected_range(int id, double measured_m) const {
    const auto it = calibrations_.find(id);
    return it == calibrations_.end() ? measured_m : it->second.corrected_range(measured_m);
  }

  bool calibrated(int id) const { return calibrations_.count(id) > 0; }
  const std::map<int, Eigen::Vector3d>& positions() const { return anchors_; }

  std::optional<Eigen::Vector3d> find(int id) const {
    const auto it = anchors_.find(id);
    if (it == anchors_.end()) return std::nullopt;
    return it->second;
  }
  // Adds an anchor the configuration did not name (configured positions win: a surveyed
  // position beats what the tag was told). Returns true when it was new.
  bool learn(int id, const Eigen::Vector3d& p_AinW) {
    if (!p_AinW.allFinite() || anchors_.count(id)) return false;
    anchors_[id] = p_AinW;
    return true;
  }
  std::size_t size() const { return anchors_.size(); }
  bool empty() const { return anchors_.empty(); }

 private:
  std::map<int, Eigen::Vector3d> anchors_;
  std::map<int, UwbAnchor> calibrations_;
};

}  // namespace luxloc
