#pragma once
// `luxloc eval --html FILE`: the evaluation as one static, self-contained HTML page (inline
// SVG and CSS, no script, nothing fetched): the trajectory against the truth, the error
// over time, the error histogram and the summary. The live view's look, for a finished run.
#include <string>
#include <vector>

#include "core/eval/trajectory_metrics.hpp"

namespace luxloc {

std::string trajectory_report_html(const std::vector<TruthRow>& truth, const EvalResult& result,
                                   const std::string& title);

}  // namespace luxloc
