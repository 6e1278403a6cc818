#pragma once
// Decoder accuracy against ground truth (issue 3's acceptance: "the decoded id is right
// for >= 99.5 % of LED blobs that lie fully inside the image and span >= 20 rows; wrong ids
// are <= 0.1 % of all decodes; a dark frame yields no LED"). Truth comes from whoever knows
// where each LED projects (the simulator's renderer, a survey); this file only matches.
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "core/vlc/led_observation.hpp"

namespace luxloc {

// Where an LED really is in a frame.
struct TrueLedBlob {
  int id = 0;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // projected centre (distorted px)
  double radius_px = 0.0;
  double row_span = 0.0;      // rows the disc spans
  bool fully_inside = false;  // the whole disc lies within the image
  int klass = -1;  // its frequency class (LedMap::class_of): a decode of a reused frequency is right by class
};

struct IdCheckOptions {
  double min_row_span = 20.0;  // qualifying blobs span at least this many rows...
  // ... and lie fully inside. A decode belongs to the true blob whose centre is nearest,
  // when it is within this fraction of that blob's radius (+ 2 px).
  double match_radius_fraction = 1.0;
};

struct IdCheckCounts {
  long frames = 0;
  long dark_frames = 0;          // frames with no LED in truth
  long dark_frame_decodes = 0;   // accepted decodes in those frames (must be 0)
  long qualifying = 0;           // true blobs fully inside and >= min_row_span rows
  long right = 0;                // ... decoded with the right id
  long missed = 0;               // ... not decoded with the right id (qualifying - right)
  std::map<std::string, long> missed_by;  // why: the decoder's reject reason, "wrong id" or "not found"
  std::map<int, long> missed_by_id;       // which LED (true id)
  long decodes = 0;              // accepted observations, all blobs
  long wrong = 0;                // accepted with an id that is not the LED there (or no LED there)
  long rejected = 0;             // blobs the decoder refused

  void add(const IdCheckCounts& o);
  double right_fraction() const { return qualifying > 0 ? static_cast<double>(right) / qualifying : 1.0; }
  double wrong_fraction() const { return decodes > 0 ? static_cast<double>(wrong) / decodes : 0.0; }
};

// Tallies one frame's decoder output against its truth. A decode counts when it names a
// frequency class (LedObservation::classified); it is right when it names the LED there, or,
// for a reused frequency (no LED named: the position tells which copy), that LED's class.
void tally_ids(const std::vector<LedObservation>& decoded, const std::vector<TrueLedBlob>& truth, IdCheckCounts& counts,
               const IdCheckOptions& options = {});

}  // namespace luxloc
