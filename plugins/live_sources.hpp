#pragma once
// Factory for the live source kinds of `--source KIND:TARGET[,key=value...]`
// (SPEC.md "Source kinds"): each plugin registers its kind here.
#include <optional>
#include <string>
#include <vector>

#include "core/common/session_config.hpp"
#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_map.hpp"

#include "core/pipeline/source.hpp"
#include "plugins/source_spec.hpp"

namespace luxloc {

// The live kinds this build knows (for --help and messages).
std::vector<std::string> live_source_kinds();
// Opens the source; throws InputError for an unknown kind or bad parameters, and
// std::runtime_error when the device cannot be opened (exit 1).
SourcePtr make_live_source(const SourceSpec& spec);

// What a live source knows about its session: the simulator knows its LED map, camera and
// device height. Fills only what is still empty (command-line files win).
struct LiveSessionDefaults {
  std::optional<LedMap> map;
  std::optional<CameraModel> camera;
  SessionConfig config;
};
void live_session_defaults(const SourceSpec& spec, LiveSessionDefaults& defaults);

}  // namespace luxloc
