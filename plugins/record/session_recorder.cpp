#include "plugins/record/session_recorder.hpp"

#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <limits>
#include <stdexcept>

#include "core/common/input_error.hpp"
#include "core/common/session_file.hpp"
#include "plugins/output/text_file.hpp"

namespace luxloc {
namespace {

namespace fs = std::filesystem;

// Exact seconds from the ns timeline: "12345.678901234" (parsing it back gives the same ns).
std::string exact_seconds(TimeNs t) {
  char buf[48];
  const bool negative = t < 0;
  const auto a = static_cast<std::uint64_t>(negative ? -t : t);
  const auto per_s = static_cast<std::uint64_t>(kNsPerSecond);
  std::snprintf(buf, sizeof buf, "%s%" PRIu64 ".%09" PRIu64, negative ? "-" : "", a / per_s, a % per_s);
  return buf;
}

}  // namespace

// Lives on the writer thread: opens each CSV at its first sample. The CSVs are TextFiles:
// after a write failure (disk full) each one holds only complete rows. The first failure
// stops the recording (reported on stderr at once); the samples after it are not written,
// and the fusion goes on.
struct SessionRecorder::Writer {
  fs::path dir;
  int png_compression = 1;
  std::map<std::string, std::unique_ptr<TextFile>> files;
  std::map<std::string, std::uint64_t> written;
  std::string error;  // first write failure: the recording stopped there
  std::atomic<bool> stopped{false};
  std::uint64_t not_written = 0;  // samples after the failure
  std::size_t frame_index = 0;

  void failed(const std::string& what) {
    if (!error.empty()) return;
    error = what;
    stopped.store(true, std::memory_order_relaxed);
    std::fprintf(stderr, "luxloc: record: %s; recording stopped (%s keeps what was written), the run goes on\n",
                 what.c_str(), dir.c_str());
  }
  TextFile* csv(const std::string& name, const char* header) {
    auto it = files.find(name);
    if (it == files.end()) {
      try {
        auto f = std::make_unique<TextFile>((dir / name).string());
        f->write(header);
        it = files.emplace(name, std::move(f)).first;
      } catch (const std::exception& e) {
        failed(e.what());
        return nullptr;
      }
    }
    return it->second.get();
  }
  void row(const std::string& name, const char* header, const std::string& line) {
    TextFile* f = csv(name, header);
    if (!f) return;
    try {
      f->write(line);
      ++written[name];
    } catch (const std::exception& e) {
      failed(e.what());
    }
  }
  // ",<v>" with 17 significant digits (round-trip exact); empty after the comma for NaN.
  static void field(std::string& line, double v) {
    char buf[32];
    line.push_back(',');
    if (std::isfinite(v)) {
      std::snprintf(buf, sizeof buf, "%.17g", v);
      line.append(buf);
    }
  }

  void write(const ImuSample& s) {
    std::string line = exact_seconds(s.t);
    for (double v : {s.acc_inB.x(), s.acc_inB.y(), s.acc_inB.z(), s.gyro_inB.x(), s.gyro_inB.y(), s.gyro_inB.z()})
      field(line, v);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (int i = 0; i < 3; ++i) field(line, s.has_mag ? s.mag_inB[i] : nan);
    line.push_back('\n');
    row("imu.csv", "t,ax,ay,az,gx,gy,gz,mx,my,mz\n", line);
  }
  void write(const FrameSample& s) {
    char name[32];
    std::snprintf(name, sizeof name, "frames/%06zu.png", frame_index++);
    std::error_code ec;
    fs::create_directories(dir / "frames", ec);
    bool ok = false;
    try {
      ok = cv::imwrite((dir / name).string(), s.gray, {cv::IMWRITE_PNG_COMPRESSION, png_compression});
    } catch (const cv::Exception&) {
      ok = false;
    }
    if (!ok) {
      fs::remove(dir / name, ec);  // no half-written PNG left behind
      failed("cannot write " + (dir / name).string() + " (disk full?)");
      return;
    }
    std::string line = exact_seconds(s.t);
    line.push_back(',');
    line.append(name).push_back('\n');
    row("frames.csv", "t,file\n", line);
  }
  void write(const UwbSample& s) {
    std::string line = exact_seconds(s.t);
    line.push_back(',');
    line.append(std::to_string(s.anchor));
    field(line, s.range_m);
    field(line, s.aoa_rad);
    line.push_back('\n');
    row("uwb.csv", "t,anchor,range_m,aoa_rad\n", line);
  }
  void write(const FixSample& s) {
    std::string line = exact_seconds(s.t);
    field(line, s.p_inW.x());
    field(line, s.p_inW.y());
    field(line, s.sigma_m);
    line.push_back('\n');
    row("fixes.csv", "t,x,y,sigma_m\n", line);
  }
  void write(const OdomSample& s) {
    std::string line = exact_seconds(s.t);
    field(line, s.dist_m);
    field(line, s.dyaw_rad);
    line.push_back('\n');
    row("odom.csv", "t,dist_m,dyaw_rad\n", line);
  }
  void close() {
    for (auto& [name, f] : files) {
      try {
        if (!f->failed()) f->flush();
      } catch (const std::exception& e) {
        failed(e.what());
      }
    }
    files.clear();
  }
};

SessionRecorder::SessionRecorder(fs::path dir, const std::optional<LedMap>& map,
                                 const std::optional<CameraModel>& camera, const SessionConfig& config,
                                 RecorderOptions options)
    : dir_(std::move(dir)), options_(options), queue_(options.queue_capacity), writer_(std::make_unique<Writer>()) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (!fs::is_directory(dir_)) throw InputError(dir_.string(), 0, "--out", "cannot create the session folder");
  for (const char* existing : {"imu.csv", "frames.csv", "uwb.csv", "fixes.csv", "odom.csv"})
    if (fs::exists(dir_ / existing))
      throw InputError((dir_ / existing).string(), 0, "--out", "the folder already holds a session: choose a new one");
  if (map) map->save((dir_ / "ledmap.yaml").string());
  if (camera) camera->save((dir_ / "camera.yaml").string());
  // The recording's own files have SPEC's default names, whatever the source session used.
  SessionConfig recorded;
  recorded.device_height_m = config.device_height_m;
  recorded.anchors = config.anchors;
  save_session_config(recorded, (dir_ / "session.yaml").string());
  writer_->dir = dir_;
  writer_->png_compression = options_.png_compression;
  thread_ = std::thread([this] { writer_loop(); });
}

SessionRecorder::~SessionRecorder() {
  std::vector<PoseEstimate> unused;
  finish(unused);
}

void SessionRecorder::process(const Sample& sample, std::vector<PoseEstimate>&) {
  if (writer_->stopped.load(std::memory_order_relaxed)) return;  // a write failed: recording is over
  SensorData copy = sample.data;
  // A frame's pixels are cloned (0.3 MB per VGA frame, one memcpy): the writer thread then
  // owns a buffer no other thread touches. Shared, the buffer's last release falls to
  // whichever thread drops it last, through OpenCV's refcount in its uninstrumented library;
  // CI's ThreadSanitizer run reported a race in the record test that we could not reproduce
  // here, and the shared buffer is the only memory both threads reach.
  if (auto* frame = std::get_if<FrameSample>(&copy)) frame->gray = frame->gray.clone();
  if (!queue_.try_push(std::move(copy))) {
    static constexpr const char* kNames[] = {"imu.csv", "frames.csv", "uwb.csv", "fixes.csv", "odom.csv"};
    ++dropped_[kNames[sample.data.index()]];
  }
}

void SessionRecorder::writer_loop() {
  for (;;) {
    const auto write = [this](const SensorData& d) {
      if (writer_->stopped.load(std::memory_order_relaxed))
        ++writer_->not_written;
      else
        std::visit([this](const auto& s) { writer_->write(s); }, d);
    };
    if (std::optional<SensorData> d = queue_.try_pop()) {
      write(*d);
      continue;
    }
    if (done_.load(std::memory_order_acquire)) {
      // The producer has stopped: whatever it pushed before is visible now.
      while (std::optional<SensorData> d = queue_.try_pop()) write(*d);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  writer_->close();
}

void SessionRecorder::finish(std::vector<PoseEstimate>&) {
  if (!thread_.joinable()) return;
  done_.store(true, std::memory_order_release);
  thread_.join();
}

RecorderStats SessionRecorder::stats() const {
  if (!writer_->error.empty()) throw std::runtime_error(writer_->error);
  return {writer_->written, dropped_};
}

std::string SessionRecorder::error() const { return writer_->error; }

}  // namespace luxloc
