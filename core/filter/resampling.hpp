#pragma once
// Resampling policies, separate from the filter (Beluga's split): each maps normalised
// weights to ancestor indices (out[i] = index of the particle that child i copies).
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace luxloc {

enum class ResamplingScheme { Systematic, Stratified, Multinomial, Residual };

ResamplingScheme parse_resampling_scheme(const std::string& name);  // throws std::invalid_argument
std::string to_string(ResamplingScheme s);

// weights: normalised (sum 1); randomness from `seed`. Draws `children` ancestors
// (0: as many as there are weights; KLD-sampling asks for other counts).
// Systematic and stratified run in parallel (TBB) over fixed chunks for large sets.
void resample(ResamplingScheme scheme, std::span<const double> weights, std::uint64_t seed,
              std::vector<std::uint32_t>& ancestors, std::size_t children = 0);

}  // namespace luxloc
