#pragma once
// Turns UwbSamples into what the filters take: a per-particle likelihood (tight coupling)
// and position fixes (loose coupling, initialisation, the EKF, the UWB-alone baseline):
// seed B.3's TOF + AOA fix for a sample with a bearing, multilateration over a group of
// ranges (>= 3 anchors within group_window_s) otherwise. Both use the device height and the
// per-anchor range biases of the HeightBiasFilter (learnt while running from observe()),
// the nominal height and zero biases where it is off.
#include <limits>
#include <optional>
#include <vector>

#include "core/common/samples.hpp"
#include "core/filter/planar_filter.hpp"
#include "core/uwb/uwb_anchor_table.hpp"
#include "core/uwb/uwb_options.hpp"
#include "core/uwb/uwb_range_likelihood.hpp"

namespace luxloc {

struct UwbStats {
  std::uint64_t samples = 0;
  std::uint64_t unknown_anchor = 0;   // no position for the anchor: skipped
  std::uint64_t rejected = 0;         // non-finite range / bearing
  std::uint64_t learnt_anchors = 0;   // anchor positions taken from the device's reports
  std::uint64_t weighed = 0;          // tight updates the particle filter took
  std::uint64_t disagreements = 0;    // tight updates far from the filter's mean
  std::uint64_t fixes = 0;            // position fixes made (B.3 or multilateration)
  std::uint64_t fixes_outside_hull = 0;  // multilateration fixes outside the anchors (a possible mirror)
  std::uint64_t reinitializations = 0;
  // Issue 16 part 6, what became of each sample; with rejected + unknown_anchor these add up
  // to samples: weighed + fixes_used + fixes_gated + no_fix + reinitializations + underflow.
  std::uint64_t fixes_used = 0;    // position fixes the filter took (loose, the EKF, the first fix, --uwb-alone)
  std::uint64_t fixes_gated = 0;   // position fixes the filter's gate refused
  std::uint64_t no_fix = 0;        // not weighed alone and no fix completed with it (yet)
  std::uint64_t start_held = 0;    // of no_fix: fixes held before the start (UwbOptions::start_agreeing_fixes)
  std::uint64_t underflow = 0;     // every particle's weight underflowed and no fix to recover at
  std::uint64_t nlos_set_aside = 0;  // ranges of an anchor flagged NLOS, not weighed (counted apart, see accounted())
  // The online height / bias filter (issue 16 parts 1, 3): ranges it used or set aside, and
  // its final states (NaN height: not estimated; biases of the anchors it learnt).
  std::uint64_t online_used = 0, online_gated_long = 0, online_gated_short = 0;
  std::uint64_t online_bias_reopened = 0;  // HeightBiasOptions::short_run_reopen
  double final_height_m = std::numeric_limits<double>::quiet_NaN();
  double final_height_sigma_m = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::pair<int, double>> learnt_bias_m;
  std::vector<std::pair<int, double>> learnt_scale;  // 1 + s per anchor (with --uwb-scale)
  std::uint64_t accounted() const {
    return unknown_anchor + rejected + weighed + fixes_used + fixes_gated + no_fix + reinitializations + underflow +
           nlos_set_aside;
  }
};

class UwbFrontend {
 public:
  UwbFrontend(const UwbOptions& options, UwbAnchorTable anchors, double z_B);

  // nullopt (counted) when the sample is unusable or its anchor unknown. Learns anchor
  // positions the sample carries.
  std::optional<UwbRangeLikelihood> likelihood(const UwbSample& s);
  // A position fix, when this sample completes one (see above). Call for every sample
  // (after likelihood(), which does the counting and learning).
  std::optional<PositionMeasurement> fix(const UwbSample& s);
  // Feeds the sample's range to the height / bias filter (started at the planar filter's
  // first estimate e). Range-only samples of known anchors.
  void observe(const UwbSample& s, const PlanarEstimate& e);
  // A height measured by another sensor (the camera geometry) into the same height state,
  // at t (after the filter started; used / gated counted in its stats).
  HeightBiasFilter::Outcome observe_height(TimeNs t, double z_m, double sigma_m);
  // Copies the height / bias filter's counts and final states into stats() (end of a run).
  void summarize_online();

  // The anchor's recent ranges were mostly set aside as long (NLOS, innovation history);
  // never true for more than a third of the anchors (then the filter is off, not they).
  bool nlos(int anchor) const;
  // The device height the measurements are weighed at (nominal or learnt) and its sigma.
  double height_m() const { return height_bias_.height_m(); }
  double height_sigma_m() const { return height_bias_.height_sigma_m(); }
  bool estimates_height() const { return height_bias_.options().estimate_height; }
  // The last fix fix() returned lies outside the anchors' hull (Multilateration::outside_hull).
  bool last_fix_outside_hull() const { return last_fix_outside_hull_; }
  const HeightBiasFilter& height_bias() const { return height_bias_; }

  const UwbOptions& options() const { return options_; }
  UwbStats& stats() { return stats_; }
  const UwbStats& stats() const { return stats_; }
  const UwbAnchorTable& anchors() const { return anchors_; }

 private:
  std::optional<PositionMeasurement> flush_group();
  // The measured range with the anchor's calibration and learnt bias removed.
  double corrected_range(const UwbSample& s) const;

  UwbOptions options_;
  UwbAnchorTable anchors_;
  UwbStats stats_;
  HeightBiasFilter height_bias_;
  std::vector<std::pair<int, RangeToAnchor>> group_;  // ranges without AOA, one per anchor
  TimeNs group_t0_ = 0;
  bool last_fix_outside_hull_ = false;
};

}  // namespace luxloc
