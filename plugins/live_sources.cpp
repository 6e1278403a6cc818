#include "plugins/live_sources.hpp"

#include "core/common/input_error.hpp"
#include "plugins/serial/serial_imu_source.hpp"
#include "plugins/uwb/uwb_serial_source.hpp"

namespace luxloc {

std::vector<std::string> live_source_kinds() { return {"serial-imu", "uwb"}; }

SourcePtr make_live_source(const SourceSpec& spec) {
  if (spec.kind == "serial-imu") return make_serial_imu_source(spec);
  if (spec.kind == "uwb") return make_uwb_serial_source(spec);
  std::string kinds = "playback";
  for (const auto& k : live_source_kinds()) kinds += ", " + k;
  throw InputError("--source", 0, "--source",
                   "'" + spec.text + "': source kind '" + spec.kind + "' is not available in this build (available: " +
                       kinds + ")");
}

}  // namespace luxloc
