#pragma once
// Writes a Simulator's session folder in SPEC.md's layout: imu.csv, frames.csv + frames/,
// groundtruth.csv, ledmap.yaml, camera.yaml, session.yaml, plus steps.csv (true heel
// strikes) and sim_truth.yaml (seed, biases, LED phases: what a calibration should recover).
#include <cstdint>
#include <filesystem>

#include "core/sim/simulator.hpp"

namespace luxloc::sim {

enum class ImageFormat { png, jpeg };

struct SessionWriteOptions {
  bool write_frames = true;  // false: no frames/ and no frames.csv (IMU-only session)
  ImageFormat format = ImageFormat::jpeg;
  int png_compression = 1;   // zlib level: 1 is ~4x faster than the default 3 and barely larger
  int jpeg_quality = 95;
  // fixes.csv: absolute 2-D fixes (any positioning system: t,x,y,sigma_m) at this rate from
  // the ground truth plus Gaussian noise of fixes_sigma_m per axis; 0: no fixes.csv.
  double fixes_rate_hz = 0.0;
  double fixes_sigma_m = 0.3;
};

struct SessionSummary {
  std::size_t frames = 0;
  std::size_t imu_samples = 0;
  std::size_t truth_rows = 0;
  std::size_t steps = 0;
  std::size_t fixes = 0;
  std::size_t uwb_rows = 0;  // uwb.csv (scenarios with UWB anchors)
  std::size_t files = 0;
  std::uintmax_t bytes = 0;      // total size of the files written
  std::uintmax_t frame_bytes = 0;
};

// Creates `dir` if needed; stale frames/NNNNNN.{png,jpg} from an earlier run are removed.
// Frames are rendered and encoded in parallel (TBB). Throws std::runtime_error on I/O failure.
SessionSummary write_session(const Simulator& sim, const std::filesystem::path& dir,
                             const SessionWriteOptions& options = {});

}  // namespace luxloc::sim
