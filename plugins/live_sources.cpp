#include "plugins/live_sources.hpp"

#include <cmath>

#include "core/common/input_error.hpp"
#include "core/sim/scenario.hpp"
#include "plugins/external/external_plugin.hpp"
#include "plugins/serial/serial_imu_source.hpp"
#include "plugins/sim/sim_source.hpp"
#include "plugins/uwb/uwb_serial_source.hpp"
#include "plugins/v4l2/v4l2_camera_source.hpp"

namespace luxloc {

std::vector<std::string> live_source_kinds() { return {"serial-imu", "v4l2", "uwb", "sim"}; }

SourcePtr make_live_source(const SourceSpec& spec) {
  if (spec.kind == "serial-imu") return make_serial_imu_source(spec);
  if (spec.kind == "v4l2") return make_v4l2_camera_source(spec);
  if (spec.kind == "uwb") return make_uwb_serial_source(spec);
  if (spec.kind == "sim") return std::make_unique<SimSource>(SimSourceOptions::from_spec(spec));
  if (SourcePtr external = make_external_source(spec)) return external;
  std::string kinds = "playback";
  for (const auto& k : live_source_kinds()) kinds += ", " + k;
  for (const auto& p : external_plugins()) kinds += ", " + p->kind() + " (" + p->path() + ")";
  throw InputError("--source", 0, "--source",
                   "'" + spec.text + "': source kind '" + spec.kind + "' is not available in this build (available: " +
                       kinds + ")");
}

void live_session_defaults(const SourceSpec& spec, LiveSessionDefaults& d) {
  if (spec.kind != "sim") return;
  const sim::Scenario sc = SimSourceOptions::from_spec(spec).scenario_with_camera();
  if (!d.map) d.map = sc.map;
  if (!d.camera) d.camera = sc.camera;
  if (!std::isfinite(d.config.device_height_m)) d.config.device_height_m = sc.device_height_m;
  if (d.config.anchors.empty()) d.config.anchors = sc.anchors;
}

}  // namespace luxloc
