#pragma once
// Heel-strike impacts out of the vertical acceleration (issue 12: "fast walking (1.7 m/s,
// 12 g peaks) keeps its step length"). A device on the leg, in a trouser pocket or on the
// hip sees each heel strike as a spike of several g lasting a few tens of milliseconds,
// right on the bounce's peak. The step detector's 0.1 s moving average does not remove it
// (a spike of zero net velocity leaves lobes of +-7 m/s^2 in a box average), so on a 12 g
// walk the detector's swing, and with it the Weinberg step length, grew by 40 %.
// The body a step moves changes its acceleration smoothly (the walk's bounce: at most
// 2 pi f a ~ 80 m/s^3); an impact jumps by g's within milliseconds. So a sample further
// than max_jump (and faster than max_jerk) from the last one handed on starts an impact. Its
// samples are held back until the signal has been back within max_jump of the value before
// it for `margin` (the spike's edges) plus `fit_window`, and then handed on as the parabola
// fitted (least squares) to the clean samples of fit_window either side: the impact sits on
// the bounce's peak, which a straight line would cut (the distance came out 2.5 % short). A
// clean stream passes sample by sample, unchanged and without delay. A change that lasts
// longer than max_hold is real (the device was put down, picked up, dropped): handed on as
// it was. docs/MOTION.md "Heel-strike impacts".
#include <cstdint>
#include <deque>
#include <utility>
#include <vector>

#include "core/common/time.hpp"

namespace luxloc {

struct ImpactFilterOptions {
  // 4 m/s^2: the simulator's bounciest walker (+-6.1 m/s^2 at 2.1 Hz) moves by 1.2 m/s^2 in
  // 15 ms, 1.6 in a 50 Hz sample; a 12 g impact by 30-100 m/s^2. On the simulator's walkers
  // without impacts (tuning seeds 1-10) no sample is held; 0 switches it off. (A variant
  // that compared with the sample 15 ms back lost 7-20 % of the steps of the real pocket
  // walks in ../shared/realdata/phone_steps at 3-4 m/s^2: a pocket's own step signature
  // jumps by that much over two samples. Not kept.)
  double max_jump_mps2 = 4.0;
  // ... and at most this per second between samples: 400 m/s^3, the 4 m/s^2 of a 100 Hz
  // sample (the rate the rest was chosen at), five times the bounciest walker's jerk, so that
  // at 200-1000 Hz a spike's edge is caught before it creeps in below max_jump a sample.
  double max_jerk_mps3 = 400.0;
  // A 12 ms-wide impact (the simulator's) leaves the band for ~70 ms, a 25 ms one ~150 ms.
  double max_hold_s = 0.2;
  // The spike's edges, inside the band: 15 ms (1-3 samples at 100-200 Hz). The samples
  // within it before the spike and after it are left out of the fit; those after it are
  // replaced too (those before were handed on already).
  double margin_s = 0.015;
  // Clean samples either side that the parabola is fitted to: 40 ms (4-8 samples at
  // 100-200 Hz; a 2 Hz bounce bends by ~6 % of its amplitude over it).
  double fit_window_s = 0.04;
};

class ImpactFilter {
 public:
  using Sample = std::pair<TimeNs, double>;
  explicit ImpactFilter(const ImpactFilterOptions& options = {}) : options_(options) {}
  // One sample of the vertical acceleration (m/s^2, gravity removed), in time order. Returns
  // the samples to hand on: this one alone on a clean stream, none while an impact lasts,
  // the repaired impact (and this sample) when it is over.
  const std::vector<Sample>& update(TimeNs t, double a_mps2);
  // The value standing for now: the last sample handed on, or the one before an impact.
  double current() const { return current_; }
  std::uint64_t repaired() const { return repaired_; }  // samples replaced so far
  const ImpactFilterOptions& options() const { return options_; }

 private:
  void release(bool repair);

  ImpactFilterOptions options_;
  std::vector<Sample> out_;
  std::deque<Sample> held_;       // the impact's samples, as measured
  std::deque<Sample> recent_;      // samples handed on over the last margin + fit_window
  std::vector<Sample> before_;     // the clean samples before the impact (fit_window)
  TimeNs t_back_ = -1;            // when the signal came back within max_jump (-1: not yet)
  double reference_ = 0.0;        // the last sample handed on (before the impact, during one)
  double current_ = 0.0;
  std::uint64_t repaired_ = 0;
};

}  // namespace luxloc
