#pragma once
// `run --check-associations` (issue 14): in a simulated session over a map that reuses
// frequencies, was each blob of a reused frequency given the right copy? Compares the
// fusion's association at its estimate (FusionEngine::AssociationRecord) with the LED the
// renderer really put at that pixel (app/sim_truth.hpp).
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "app/sim_truth.hpp"
#include "core/fusion/fusion_engine.hpp"

namespace luxloc::app {

struct AssociationCheck {
  long frames = 0, blobs = 0;  // frames with reused blobs weighed in, and those blobs
  long localising = 0;         // blobs weighed while the filter still searched (not judged)
  long judged = 0;             // blobs weighed while tracking...
  long right = 0;              // ... given the LED that is there
  long wrong = 0;              // ... given another copy of the class
  long unassociated = 0;       // ... no copy of the class near the estimate
  long no_truth = 0;           // ... no true LED at the blob (a decoder artefact)
  long wrong_frames = 0;       // frames with at least one wrong copy
  double first_wrong_s = std::numeric_limits<double>::quiet_NaN();
  double last_wrong_s = std::numeric_limits<double>::quiet_NaN();
};

AssociationCheck check_associations(const std::vector<FusionEngine::AssociationRecord>& records, const SimTruth& truth,
                                    const std::vector<std::pair<double, double>>& blackouts, const CameraModel& camera,
                                    const LedMap& map);
// One line for the run report.
std::string describe(const AssociationCheck& c);

}  // namespace luxloc::app
