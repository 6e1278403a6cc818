#include "core/vlc/id_check.hpp"

namespace luxloc {

void IdCheckCounts::add(const IdCheckCounts& o) {
  frames += o.frames;
  dark_frames += o.dark_frames;
  dark_frame_decodes += o.dark_frame_decodes;
  qualifying += o.qualifying;
  right += o.right;
  missed += o.missed;
  for (const auto& [k, v] : o.missed_by) missed_by[k] += v;
  for (const auto& [k, v] : o.missed_by_id) missed_by_id[k] += v;
  decodes += o.decodes;
  wrong += o.wrong;
  rejected += o.rejected;
}

namespace {

// Index of the true blob that `uv` belongs to, or -1.
int owner(const Eigen::Vector2d& uv, const std::vector<TrueLedBlob>& truth, const IdCheckOptions& options) {
  int best = -1;
  double best_d = 1e300;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const double d = (truth[i].uv - uv).norm();
    if (d < best_d && d <= options.match_radius_fraction * truth[i].radius_px + 2.0) {
      best_d = d;
      best = static_cast<int>(i);
    }
  }
  return best;
}

// The decode names the LED there (its id, or its class when the frequency is reused).
bool names(const LedObservation& o, const TrueLedBlob& t) {
  if (!o.classified()) return false;
  return o.accepted() ? o.led_id == t.id : o.freq_class == t.klass;
}

}  // namespace

void tally_ids(const std::vector<LedObservation>& decoded, const std::vector<TrueLedBlob>& truth, IdCheckCounts& counts,
               const IdCheckOptions& options) {
  ++counts.frames;
  if (truth.empty()) ++counts.dark_frames;
  // Which decode (if any) each true blob got: the accepted one nearest to it, else a rejected one.
  std::vector<const LedObservation*> got(truth.size(), nullptr);
  for (const LedObservation& o : decoded) {
    const int k = owner(o.uv, truth, options);
    if (!o.classified()) {
      ++counts.rejected;
      if (k >= 0 && !got[static_cast<std::size_t>(k)]) got[static_cast<std::size_t>(k)] = &o;
      continue;
    }
    ++counts.decodes;
    if (truth.empty()) ++counts.dark_frame_decodes;
    if (k < 0 || !names(o, truth[static_cast<std::size_t>(k)])) ++counts.wrong;
    if (k >= 0) {
      const TrueLedBlob& t = truth[static_cast<std::size_t>(k)];
      const LedObservation*& g = got[static_cast<std::size_t>(k)];
      if (!g || !g->classified() || (!names(*g, t) && names(o, t))) g = &o;
    }
  }
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const TrueLedBlob& t = truth[i];
    if (!t.fully_inside || t.row_span < options.min_row_span) continue;
    ++counts.qualifying;
    const LedObservation* g = got[i];
    if (g && names(*g, t)) {
      ++counts.right;
      continue;
    }
    ++counts.missed;
    counts.missed_by_id[t.id]++;
    counts.missed_by[!g ? "not found" : g->classified() ? "wrong id" : g->reject_reason]++;
  }
}

}  // namespace luxloc
