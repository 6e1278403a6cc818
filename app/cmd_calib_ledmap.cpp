// `luxloc calib ledmap survey|refine|check`: getting a trustworthy LED map on day one
// (calib/led_map_calibration.*):
//   survey  stand under a light (or hold the camera at a known point): measures the LED's
//           blink frequency from the stripes, proposes an id, appends it with the position;
//   refine  LED positions by least squares over all bearing rays of a recorded session with
//           known poses (ground truth or a trusted run), per-LED residuals, a corrected map;
//   check   a map against a session: LEDs never seen, drifting or inseparable frequencies
//           (with the spacing the decoder needs), LEDs whose observed position disagrees;
//   plan    frequencies for a floor of lights, reused out of each other's view
//           (app/cmd_calib_ledmap_plan.cpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unistd.h>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/run_session.hpp"
#include "calib/led_map_calibration.hpp"
#include "core/common/csv_reader.hpp"
#include "core/common/input_error.hpp"
#include "core/eval/trajectory_io.hpp"
#include "core/imu/mahony_filter.hpp"
#include "core/vlc/stripe_decoder.hpp"

namespace luxloc::app {
namespace {

namespace fs = std::filesystem;

LedMapOptions relaxed_map_options() {
  LedMapOptions o;
  o.min_relative_separation = 0.0;  // a map under check may hold inseparable frequencies
  return o;
}

// Reads the session's frames (decoding each right away) and IMU samples.
struct DecodedSession {
  std::vector<TimedLedSighting> sightings;
  std::vector<ImuSample> imu;
  std::size_t frames = 0, blobs = 0, rejected = 0;
  std::optional<CameraModel> camera;
  SessionConfig config;
};

DecodedSession decode_session(const std::string& dir, const LedMap& map, const std::string& camera_path) {
  RunConfig rc;
  rc.playback = dir;
  rc.camera = camera_path;
  OpenedSources opened = open_run_sources(rc);
  DecodedSession d;
  d.camera = opened.session.camera;
  d.config = opened.session.config;
  if (!d.camera) throw InputError(dir, 0, "camera.yaml", "the session has no camera file (give --camera)");
  const StripeDecoder decoder(*d.camera, map);
  const bool tty = isatty(fileno(stderr)) != 0;  // progress only on a terminal
  for (SourcePtr& src : opened.session.sources) {
    SensorData s;
    while (src->next(s)) {
      if (const auto* f = std::get_if<FrameSample>(&s)) {
        if (tty && ++d.frames % 100 == 0) std::fprintf(stderr, "\rcalib ledmap: %zu frames decoded", d.frames);
        if (!tty) ++d.frames;
        const std::vector<LedObservation> obs = decoder.decode(f->gray);
        d.blobs += obs.size();
        for (const LedObservation& o : obs) d.rejected += o.accepted() ? 0 : 1;
        const auto sg = sightings_of_frame(f->t, obs, *d.camera);
        d.sightings.insert(d.sightings.end(), sg.begin(), sg.end());
      } else if (const auto* i = std::get_if<ImuSample>(&s)) {
        d.imu.push_back(*i);
      }
    }
  }
  if (tty && d.frames >= 100) std::fputc('\n', stderr);
  if (d.frames == 0) throw InputError(dir, 0, "frames.csv", "the session has no readable frames");
  return d;
}

// roll and pitch columns of a CSV pose file (ground truth, a luxloc run), by time; empty
// when the file has none (or is TUM).
std::map<TimeNs, Eigen::Vector2d> roll_pitch_columns(const std::string& path) {
  std::map<TimeNs, Eigen::Vector2d> out;
  try {
    CsvReader r(path);
    const int t = r.column("t"), roll = r.column("roll"), pitch = r.column("pitch");
    if (t < 0 || roll < 0 || pitch < 0) return out;
    while (r.next_row()) {
      const double vr = r.number_or(roll, std::nan("")), vp = r.number_or(pitch, std::nan(""));
      if (std::isfinite(vr) && std::isfinite(vp)) out[seconds_to_ns(r.number(t))] = {vr, vp};
    }
  } catch (const InputError&) {
    out.clear();  // not a CSV with those columns: the IMU gives roll and pitch
  }
  return out;
}

// Device poses: positions (and yaw, roll, pitch where given) from the poses file; what it
// lacks from the Mahony filter over the session's IMU.
PoseTrack pose_track(const std::string& poses_path, const std::vector<ImuSample>& imu) {
  std::vector<PoseRow> rows = read_pose_file(poses_path);
  std::sort(rows.begin(), rows.end(), [](const PoseRow& a, const PoseRow& b) { return a.t < b.t; });
  const std::map<TimeNs, Eigen::Vector2d> tilt = roll_pitch_columns(poses_path);
  MahonyFilter ahrs;
  std::vector<TimeNs> t_att;
  std::vector<Eigen::Vector3d> rpy;
  for (const ImuSample& s : imu) {
    ahrs.update(s);
    if (!ahrs.initialized()) continue;
    t_att.push_back(s.t);
    rpy.emplace_back(ahrs.roll(), ahrs.pitch(), ahrs.yaw());
  }
  PoseTrack track;
  for (const PoseRow& r : rows) {
    Eigen::Vector3d a = Eigen::Vector3d::Zero();  // no IMU: level device
    if (!t_att.empty()) {
      const auto it = std::lower_bound(t_att.begin(), t_att.end(), r.t);
      a = rpy[std::min<std::size_t>(static_cast<std::size_t>(it - t_att.begin()), rpy.size() - 1)];
    }
    if (const auto it = tilt.find(r.t); it != tilt.end()) a.head<2>() = it->second;
    const double yaw = std::isfinite(r.yaw) ? r.yaw : a.z();
    DevicePose p;
    p.p_BinW = r.p_inW;
    p.q_BtoW = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(a.y(), Eigen::Vector3d::UnitY()) *
               Eigen::AngleAxisd(a.x(), Eigen::Vector3d::UnitX());
    track.add(r.t, p);
  }
  if (track.size() < 2) throw InputError(poses_path, 0, "t", "fewer than two poses");
  return track;
}

// ---- refine -------------------------------------------------------------------------------
struct RefineArgs {
  std::string playback, map, poses, out, camera;
  bool fix_z = false;
  std::size_t min_sightings = LedRefineOptions{}.min_sightings;
};

int run_refine(const RefineArgs& a) {
  const LedMap map = LedMap::load(a.map, relaxed_map_options());
  DecodedSession d = decode_session(a.playback, map, a.camera);
  const PoseTrack track = pose_track(a.poses, d.imu);
  LedRefineOptions o;
  o.fix_z = a.fix_z;
  o.min_sightings = a.min_sightings;
  const LedRefineReport r = refine_led_map(map, *d.camera, d.sightings,
                                           [&track](TimeNs t) { return track.at(t); }, o);
  std::printf("calib ledmap refine: %zu frames, %zu LED sightings, %zu poses%s\n", d.frames, d.sightings.size(),
              track.size(), a.fix_z ? " (heights kept)" : "");
  std::printf("  %4s %6s %24s %24s %8s %8s\n", "id", "seen", "map x,y,z (m)", "refined x,y,z (m)", "moved", "rms");
  std::size_t kept = 0;
  for (const LedRefinement& l : r.leds) {
    std::printf("  %4d %6zu %8.3f,%7.3f,%7.3f ", l.id, l.sightings, l.before.x(), l.before.y(), l.before.z());
    if (l.refined) {
      std::printf("%8.3f,%7.3f,%7.3f %7.3f %7.3f\n", l.after.x(), l.after.y(), l.after.z(), (l.after - l.before).norm(),
                  l.rms_m);
    } else {
      ++kept;
      std::printf("%24s (kept: fewer than %zu sightings)\n", "-", a.min_sightings);
    }
  }
  r.map.save(a.out);
  std::printf("  -> %s (%zu LEDs refined, %zu kept as they were)\n", a.out.c_str(), r.leds.size() - kept, kept);
  return 0;
}

// ---- check --------------------------------------------------------------------------------
struct CheckArgs {
  std::string playback, map, poses, camera;
  double threshold_m = LedCheckOptions{}.position_threshold_m;
};

int run_check(const CheckArgs& a) {
  const LedMap map = LedMap::load(a.map, relaxed_map_options());
  DecodedSession d = decode_session(a.playback, map, a.camera);
  std::optional<PoseTrack> track;
  if (!a.poses.empty()) track = pose_track(a.poses, d.imu);
  const PoseLookup lookup = [&track](TimeNs t) { return track->at(t); };
  LedCheckOptions o;
  o.position_threshold_m = a.threshold_m;
  o.rel_tolerance = StripeDecoderOptions{}.rel_tolerance;
  const LedCheckReport r = check_led_map(map, *d.camera, d.sightings, track ? &lookup : nullptr, o);
  std::printf("calib ledmap check: %s against %s: %zu frames, %zu blobs, %zu LED sightings, %zu blobs refused\n",
              a.map.c_str(), a.playback.c_str(), d.frames, d.blobs, d.sightings.size(), d.rejected);
  std::printf("  %4s %6s %10s %10s %8s\n", "id", "seen", "map Hz", "mean Hz", "std Hz");
  for (const LedFrequencyStats& f : r.frequencies) {
    std::printf("  %4d %6zu %10.1f ", f.id, f.sightings, f.map_hz);
    if (f.sightings == 0)
      std::printf("%10s %8s\n", "-", "-");
    else
      std::printf("%10.1f %8.1f%s\n", f.mean_hz, f.std_hz, f.drifts ? "  DRIFT: off the map's frequency" : "");
  }
  int problems = 0;
  for (int id : r.never_seen) {
    std::printf("  NEVER SEEN: LED %d (not in view, off, or its frequency is wrong in the map)\n", id);
    ++problems;
  }
  for (const LedFrequencyStats& f : r.frequencies)
    if (f.drifts) {
      std::printf("  DRIFT: LED %d blinks at %.1f Hz, the map says %.1f Hz\n", f.id, f.mean_hz, f.map_hz);
      ++problems;
    }
  std::printf("  decoder frequency noise at this camera (row time %.1f us): %.2f %% (1 sigma); the decoder needs "
              "frequencies %.1f %% apart\n",
              d.camera->row_time_s * 1e6, 100.0 * r.relative_sigma, 100.0 * r.needed_relative_spacing);
  for (const LedCollision& c : r.collisions) {
    std::printf("  INSEPARABLE: LEDs %d and %d are %.1f Hz apart; this camera needs at least %.1f Hz\n", c.id_a,
                c.id_b, c.gap_hz, c.needed_hz);
    ++problems;
  }
  if (r.checked_positions) {
    for (const LedMisplacement& m : r.misplaced) {
      std::printf("  MISPLACED: LED %d is seen at %.3f, %.3f, %.3f: %.3f m from the map (threshold %.3f m)\n", m.id,
                  m.observed.x(), m.observed.y(), m.observed.z(), m.distance_m, a.threshold_m);
      ++problems;
    }
  } else {
    std::printf("  (positions not checked: give --poses)\n");
  }
  std::printf("  %d problem%s found\n", problems, problems == 1 ? "" : "s");
  return 0;
}

// ---- survey -------------------------------------------------------------------------------
struct SurveyArgs {
  std::string playback, camera, map;
  std::vector<std::string> sources;
  std::vector<double> at;  // x, y, z of the LED
  int id = -1;
  std::size_t frames = 60;
  double min_hz = 200.0, max_hz = 10000.0;
};

int run_survey(const SurveyArgs& a) {
  if (a.at.size() != 3) throw InputError("--at", 0, "--at", "give the LED's position as X,Y,Z in metres");
  RunConfig rc;
  rc.playback = a.playback;
  rc.sources = a.sources;
  rc.camera = a.camera;
  OpenedSources opened = open_run_sources(rc);
  if (!opened.session.camera) throw InputError("--camera", 0, "--camera", "survey needs the camera file");
  const CameraModel& cam = *opened.session.camera;
  StripeDecoderOptions dopt;
  dopt.min_freq_hz = a.min_hz;
  dopt.max_freq_hz = a.max_hz;
  const StripeDecoder decoder(cam, LedMap{}, dopt);
  // The LED being surveyed is the blob nearest the image centre in each frame.
  std::vector<double> freqs;
  std::size_t frames = 0;
  for_each_frame(
      opened, [&] { return frames < a.frames; },
      [&](const FrameSample& f) {
        ++frames;
        const LedObservation* best = nullptr;
        double best_d = 1e18;
        const std::vector<LedObservation> obs = decoder.decode(f.gray);
        for (const LedObservation& o : obs) {
          if (o.reject_reason != "no map match" || o.touches_border || !(o.freq_hz > 0)) continue;
          const double dist = (o.uv - Eigen::Vector2d(cam.cx, cam.cy)).norm();
          if (dist < best_d) {
            best_d = dist;
            best = &o;
          }
        }
        if (best) freqs.push_back(best->freq_hz);
      });
  if (freqs.size() < 3)
    throw InputError("survey", 0, "frames",
                     "an LED with stripes was found in " + std::to_string(freqs.size()) + " of " +
                         std::to_string(frames) + " frames: stand under the light, short exposure");
  std::sort(freqs.begin(), freqs.end());
  const double f_med = freqs[freqs.size() / 2];
  std::vector<double> dev;
  for (double f : freqs) dev.push_back(std::abs(f - f_med));
  std::sort(dev.begin(), dev.end());
  const double sigma = 1.4826 * dev[dev.size() / 2];
  std::vector<Led> leds;
  if (fs::exists(a.map)) leds = LedMap::load(a.map).leds();
  int id = a.id;
  if (id < 0) {
    id = 1;
    for (const Led& l : leds) id = std::max(id, l.id + 1);
  }
  for (const Led& l : leds) {
    if (l.id == id) throw InputError(a.map, 0, "id", "LED " + std::to_string(id) + " is in the map already");
    const double needed = std::max(LedMapOptions{}.min_relative_separation, 6.0 * sigma / f_med) * std::min(l.freq_hz, f_med);
    if (std::abs(l.freq_hz - f_med) < needed)
      throw InputError(a.map, 0, "freq_hz",
                       "the measured " + std::to_string(f_med) + " Hz is too close to LED " + std::to_string(l.id) +
                           " (" + std::to_string(l.freq_hz) + " Hz): this camera needs " + std::to_string(needed) +
                           " Hz between LEDs");
  }
  Led led;
  led.id = id;
  led.freq_hz = f_med;
  led.p_inW = {a.at[0], a.at[1], a.at[2]};
  leds.push_back(led);
  LedMap(leds, a.map).save(a.map);
  std::printf("calib ledmap survey: LED %d at %.3f, %.3f, %.3f blinks at %.1f Hz (+-%.1f Hz over %zu of %zu frames)\n",
              id, a.at[0], a.at[1], a.at[2], f_med, sigma, freqs.size(), frames);
  std::printf("  -> %s (%zu LEDs)\n", a.map.c_str(), leds.size());
  return 0;
}

}  // namespace

void add_calib_ledmap(CLI::App& calib, Action& action) {
  CLI::App* cmd = calib.add_subcommand("ledmap", "LED map: survey lights, refine positions from a session, check a map, plan frequencies");
  cmd->require_subcommand(1);

  auto r = std::make_shared<RefineArgs>();
  CLI::App* refine = cmd->add_subcommand("refine", "LED positions by least squares over a session with known poses");
  refine->add_option("--playback", r->playback, "recorded session (frames, IMU)")->required()->check(CLI::ExistingDirectory);
  refine->add_option("--map", r->map, "LED map to refine (frequencies right, positions approximate)")->required();
  refine->add_option("--poses", r->poses, "device poses: groundtruth.csv or a trusted luxloc run (CSV or TUM)")
      ->required();
  refine->add_option("--out", r->out, "refined map to write")->required();
  refine->add_option("--camera", r->camera, "camera file (default: the session's)");
  refine->add_flag("--fix-z", r->fix_z, "keep each LED's height from the map (known ceiling)");
  refine->add_option("--min-sightings", r->min_sightings, "fewer sightings: the LED keeps its position")
      ->capture_default_str();
  refine->callback([r, &action] { action = [r] { return run_refine(*r); }; });

  auto c = std::make_shared<CheckArgs>();
  CLI::App* check = cmd->add_subcommand("check", "check a map against a session: unseen LEDs, frequencies, positions");
  check->add_option("--playback", c->playback, "recorded session")->required()->check(CLI::ExistingDirectory);
  check->add_option("--map", c->map, "LED map to check")->required();
  check->add_option("--poses", c->poses, "device poses, to check LED positions (groundtruth.csv or a trusted run)");
  check->add_option("--camera", c->camera, "camera file (default: the session's)");
  check->add_option("--threshold", c->threshold_m, "position disagreement flagged above, m")->capture_default_str();
  check->callback([c, &action] { action = [c] { return run_check(*c); }; });

  auto s = std::make_shared<SurveyArgs>();
  CLI::App* survey = cmd->add_subcommand("survey", "measure the LED above the camera and append it to a map");
  survey->add_option("--playback", s->playback, "a session recorded under the light");
  survey->add_option("--source", s->sources, "live camera instead (v4l2:/dev/videoN,exposure_us=100)");
  survey->add_option("--camera", s->camera, "camera file (default: the session's)");
  survey->add_option("--map", s->map, "map to append to (created if missing)")->required();
  survey->add_option("--at", s->at, "the LED's position X,Y,Z in metres")->required()->delimiter(',')->expected(3);
  survey->add_option("--id", s->id, "id to give (default: the next free one)");
  survey->add_option("--frames", s->frames, "frames to measure")->capture_default_str();
  survey->add_option("--min-hz", s->min_hz, "lowest frequency searched")->capture_default_str();
  survey->add_option("--max-hz", s->max_hz, "highest frequency searched")->capture_default_str();
  survey->callback([s, &action] { action = [s] { return run_survey(*s); }; });

  add_calib_ledmap_plan(*cmd, action);  // app/cmd_calib_ledmap_plan.cpp
}

}  // namespace luxloc::app
