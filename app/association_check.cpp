#include "app/association_check.hpp"

#include <cmath>
#include <cstdio>

#include "core/common/time.hpp"

namespace luxloc::app {

AssociationCheck check_associations(const std::vector<FusionEngine::AssociationRecord>& records, const SimTruth& truth,
                                    const std::vector<std::pair<double, double>>& blackouts, const CameraModel& camera,
                                    const LedMap& map) {
  AssociationCheck c;
  sim::RenderOptions render;  // noise-free: only the geometry matters
  render.read_noise_dn = 0.0;
  render.shot_noise = false;
  std::mt19937_64 rng(1);
  for (const FusionEngine::AssociationRecord& r : records) {
    ++c.frames;
    c.blobs += static_cast<long>(r.blobs.size());
    if (r.localising) {
      c.localising += static_cast<long>(r.blobs.size());
      continue;
    }
    const double t = ns_to_seconds(r.t_frame);
    bool dark = false;
    for (const auto& [s, d] : blackouts) dark = dark || (t >= s && t < s + d);
    const std::vector<TrueLedBlob> seen =
        dark || truth.rows.size() < 2 ? std::vector<TrueLedBlob>{} : true_led_blobs(truth, camera, map, t, render, rng);
    bool wrong_here = false;
    for (const auto& b : r.blobs) {
      ++c.judged;
      // The true LED whose disc holds the blob centre (as the id check matches: radius + 2 px).
      const TrueLedBlob* owner = nullptr;
      double best = 1e300;
      for (const TrueLedBlob& s : seen) {
        const double d = (s.uv - b.uv).norm();
        if (d < best && d <= s.radius_px + 2.0) {
          best = d;
          owner = &s;
        }
      }
      if (!owner) {
        ++c.no_truth;
        continue;
      }
      if (b.led_index < 0) {
        ++c.unassociated;
        continue;
      }
      if (map.leds()[static_cast<std::size_t>(b.led_index)].id == owner->id) {
        ++c.right;
      } else {
        ++c.wrong;
        wrong_here = true;
      }
    }
    if (wrong_here) {
      ++c.wrong_frames;
      if (!std::isfinite(c.first_wrong_s)) c.first_wrong_s = t;
      c.last_wrong_s = t;
    }
  }
  return c;
}

std::string describe(const AssociationCheck& c) {
  char line[512];
  std::snprintf(line, sizeof line,
                "associations (against the simulator's truth): %ld blobs of reused frequencies in %ld frames; %ld while "
                "localising (not judged); tracking %ld: right copy %ld, wrong copy %ld in %ld frames, no copy near the "
                "estimate %ld, no true LED there %ld",
                c.blobs, c.frames, c.localising, c.judged, c.right, c.wrong, c.wrong_frames, c.unassociated, c.no_truth);
  std::string s = line;
  if (c.wrong > 0) {
    std::snprintf(line, sizeof line, " (wrong copies from t = %.2f s to %.2f s)", c.first_wrong_s, c.last_wrong_s);
    s += line;
  }
  return s;
}

}  // namespace luxloc::app
