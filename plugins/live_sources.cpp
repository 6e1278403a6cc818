#include "plugins/live_sources.hpp"

#include "core/common/input_error.hpp"

namespace luxloc {

std::vector<std::string> live_source_kinds() { return {}; }

SourcePtr make_live_source(const SourceSpec& spec) {
  std::string kinds = "playback";
  for (const auto& k : live_source_kinds()) kinds += ", " + k;
  throw InputError("--source", 0, "--source",
                   "'" + spec.text + "': source kind '" + spec.kind + "' is not available in this build (available: " +
                       kinds + ")");
}

}  // namespace luxloc
