#pragma once
// `luxloc record`: the pipeline's one consuming stage, writing every sample it is handed into
// a SPEC.md session folder — imu.csv, frames.csv + frames/NNNNNN.png (lossless), uwb.csv,
// fixes.csv, odom.csv, plus ledmap.yaml / camera.yaml / session.yaml when known — so that a
// live run can be replayed bit for bit: times are written as exact nanoseconds and numbers
// with 17 significant digits (round-trip exact).
//
// Recording never stalls the sources: the stage hands samples to a writer thread through a
// bounded lock-free queue; when the disk falls behind and the queue is full, the sample is
// dropped and counted per kind (reported at the end), and the pipeline goes on. When a write
// fails (disk full) the recording stops with a message on stderr and the pipeline goes on.
#include <atomic>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <thread>

#include "core/common/session_config.hpp"
#include "core/pipeline/fusion_stage.hpp"
#include "core/pipeline/spsc_queue.hpp"
#include "core/vlc/camera_model.hpp"
#include "core/vlc/led_map.hpp"

namespace luxloc {

struct RecorderOptions {
  std::size_t queue_capacity = 1024;  // samples in flight to the writer (~300 MB of VGA frames at most)
  int png_compression = 1;            // zlib level of the frame files (fast; lossless anyway)
};

struct RecorderStats {
  std::map<std::string, std::uint64_t> written;  // per file: imu.csv, frames.csv, ...
  std::map<std::string, std::uint64_t> dropped;  // queue full (disk too slow)
};

class SessionRecorder final : public FusionStage {
 public:
  // Creates `dir` (it must not hold a session already: imu.csv or frames.csv) and writes the
  // map, camera and session.yaml at once. Throws InputError when the folder is unusable.
  SessionRecorder(std::filesystem::path dir, const std::optional<LedMap>& map,
                  const std::optional<CameraModel>& camera, const SessionConfig& config, RecorderOptions options = {});
  ~SessionRecorder() override;
  SessionRecorder(const SessionRecorder&) = delete;
  SessionRecorder& operator=(const SessionRecorder&) = delete;

  void process(const Sample& sample, std::vector<PoseEstimate>& out) override;
  // Drains the queue, closes every file. Safe to call more than once.
  void finish(std::vector<PoseEstimate>& out) override;

  // After finish(). Throws std::runtime_error when a write failed (disk full, ...).
  RecorderStats stats() const;
  // After finish(): the write failure that stopped the recording (empty when none). The
  // files then hold complete rows only, up to the failure.
  std::string error() const;

 private:
  struct Writer;
  void writer_loop();

  std::filesystem::path dir_;
  RecorderOptions options_;
  SpscQueue<SensorData> queue_;
  std::map<std::string, std::uint64_t> dropped_;  // fusion thread only
  std::unique_ptr<Writer> writer_;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

}  // namespace luxloc
