#pragma once
// Factory for the live source kinds of `--source KIND:TARGET[,key=value...]`
// (SPEC.md "Source kinds"): each plugin registers its kind here.
#include <string>
#include <vector>

#include "core/pipeline/source.hpp"
#include "plugins/source_spec.hpp"

namespace luxloc {

// The live kinds this build knows (for --help and messages).
std::vector<std::string> live_source_kinds();
// Opens the source; throws InputError for an unknown kind or bad parameters, and
// std::runtime_error when the device cannot be opened (exit 1).
SourcePtr make_live_source(const SourceSpec& spec);

}  // namespace luxloc
