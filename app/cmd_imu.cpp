// `luxloc imu`: a standalone attitude and heading reference (SEEDS.md C.1-C.3) for any IMU
// log in SPEC.md's imu.csv form or a live serial IMU. One output row per IMU sample:
//   t,roll,pitch,yaw,qw,qx,qy,qz   (s, rad ZYX Euler angles, quaternion body -> world ENU)
// then what the filter learnt and refused at that sample:
//   bias_gx,bias_gy,bias_gz,mag_rejected,acc_rejected,still   (rad/s, 0/1 flags)
// Optional: pedestrian dead reckoning (--steps) and a comparison with a simulator's truth
// (--truth), which prints the figures docs/IMU.md quotes.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "core/common/csv_reader.hpp"
#include "core/common/input_error.hpp"
#include "core/imu/imu_calibration.hpp"
#include "core/imu/mahony_filter.hpp"
#include "core/imu/pdr.hpp"
#include "core/imu/step_matching.hpp"
#include "plugins/live_sources.hpp"
#include "plugins/output/text_file.hpp"
#include "plugins/playback/imu_csv_source.hpp"

namespace luxloc::app {
namespace {

namespace fs = std::filesystem;

struct ImuArgs {
  std::string in;
  std::string source;
  std::string out;
  std::string imu_calib;
  std::string truth;
  std::string steps;
  std::string step_model = "weinberg";
  bool no_mag = false;
  double kp = kMahonyDefaults.kp;
  double ki = kMahonyDefaults.ki;
  double kp_heading = kMahonyDefaults.kp_heading;
  double ki_heading = kMahonyDefaults.ki_heading;
  double mag_gate_deg = kMahonyDefaults.mag_heading_gate_rad * 180.0 / std::numbers::pi;
  double mag_rejection = kMahonyDefaults.mag_rejection;
  bool no_bias_at_rest = false;
  bool no_still_mag_turn = false;
  bool no_impact_filter = false;
  double duration_s = 0.0;
};

// Ground truth attitude (the simulator's groundtruth.csv: t,x,y[,z],yaw,roll,pitch).
struct TruthAttitude {
  std::vector<double> t, x, y, yaw, roll, pitch;
  bool has_tilt = false;
};

TruthAttitude read_truth(const std::string& path) {
  CsvReader r(path);
  const int ct = r.require_column("t"), cx = r.require_column("x"), cy = r.require_column("y");
  const int cyaw = r.require_column("yaw"), croll = r.column("roll"), cpitch = r.column("pitch");
  TruthAttitude a;
  a.has_tilt = croll >= 0 && cpitch >= 0;
  while (r.next_row()) {
    a.t.push_back(r.number(ct));
    a.x.push_back(r.number(cx));
    a.y.push_back(r.number(cy));
    a.yaw.push_back(r.number(cyaw));
    a.roll.push_back(a.has_tilt ? r.number(croll) : 0.0);
    a.pitch.push_back(a.has_tilt ? r.number(cpitch) : 0.0);
  }
  if (a.t.size() < 2) throw InputError(path, 0, "t", "needs at least 2 rows");
  return a;
}

double wrap(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

// Index of the truth row nearest to t (truth and IMU share the sim's 100 Hz clock).
std::size_t nearest(const std::vector<double>& t, double x) {
  auto it = std::lower_bound(t.begin(), t.end(), x);
  if (it == t.end()) return t.size() - 1;
  const std::size_t i = static_cast<std::size_t>(it - t.begin());
  return (i > 0 && x - t[i - 1] < t[i] - x) ? i - 1 : i;
}

std::vector<double> read_step_times(const std::string& path) {
  CsvReader r(path);
  const int ct = r.require_column("t");
  std::vector<double> t;
  while (r.next_row()) t.push_back(r.number(ct));
  return t;
}

std::atomic<Source*> g_live{nullptr};
extern "C" void on_imu_stop_signal(int) {
  if (Source* s = g_live.load()) s->request_stop();  // atomic store + write(): async-signal-safe
}

int run_imu(const ImuArgs& a) {
  // Input: a file (or a session folder holding imu.csv), or a live source.
  SourcePtr source;
  if (!a.in.empty()) {
    std::string path = a.in;
    if (fs::is_directory(path)) path = (fs::path(path) / "imu.csv").string();
    source = std::make_unique<ImuCsvSource>(path);
  } else {
    source = make_live_source(SourceSpec::parse(a.source));
  }
  ImuCalibration calib;
  if (!a.imu_calib.empty()) calib = load_imu_calibration(a.imu_calib);
  TruthAttitude truth;
  if (!a.truth.empty()) truth = read_truth(a.truth);

  MahonyOptions mo;
  mo.kp = a.kp;
  mo.ki = a.ki;
  mo.kp_heading = a.kp_heading;
  mo.ki_heading = a.ki_heading;
  mo.mag_heading_gate_rad = a.mag_gate_deg * std::numbers::pi / 180.0;
  mo.mag_rejection = a.mag_rejection;
  mo.bias_at_rest = !a.no_bias_at_rest;
  mo.still_checks_mag_turn = !a.no_still_mag_turn;
  mo.use_magnetometer = !a.no_mag;
  MahonyFilter ahrs(mo);
  PdrOptions po;
  po.length.kind = parse_step_length_kind(a.step_model);
  if (a.no_impact_filter) po.impacts.max_jump_mps2 = 0.0;
  PedestrianDeadReckoning pdr(po);
  const bool want_steps = !a.steps.empty();

  TextFile out(a.out);
  // SPEC's columns first and in order; the filter's state after them.
  out.write("t,roll,pitch,yaw,qw,qx,qy,qz,bias_gx,bias_gy,bias_gz,mag_rejected,acc_rejected,still\n");
  std::unique_ptr<TextFile> steps_out;
  if (want_steps) {
    steps_out = std::make_unique<TextFile>(a.steps);
    steps_out->write("t,length_m,heading_rad,x,y\n");
  }

  // Live sources stop on Ctrl-C / SIGTERM (and after --duration).
  g_live.store(source->live() ? source.get() : nullptr);
  auto old_int = std::signal(SIGINT, on_imu_stop_signal);
  auto old_term = std::signal(SIGTERM, on_imu_stop_signal);

  std::uint64_t n = 0;
  double se_roll = 0, se_pitch = 0, se_yaw = 0, yaw_err_end = 0;
  double yaw0_est = 0, yaw0_true = 0;
  std::size_t n_cmp = 0;
  std::vector<double> yaw_abs_err;  // |yaw error| per compared sample, for the percentiles
  std::vector<double> step_times;
  Eigen::Vector2d p0 = Eigen::Vector2d::Zero();
  std::optional<TimeNs> t_first;
  char line[256];
  SensorData d;
  while (source->next(d)) {
    const ImuSample* raw = std::get_if<ImuSample>(&d);
    if (!raw) continue;
    const ImuSample s = calib.apply(*raw);
    if (!t_first) t_first = s.t;
    ahrs.update(s);
    if (!ahrs.initialized()) continue;
    const Eigen::Quaterniond& q = ahrs.q_BtoW();
    const double t = ns_to_seconds(s.t);
    const Eigen::Vector3d& b = ahrs.gyro_bias();
    std::snprintf(line, sizeof line, "%.6f,%.6f,%.6f,%.6f,%.7f,%.7f,%.7f,%.7f,%.6f,%.6f,%.6f,%d,%d,%d\n", t,
                  ahrs.roll(), ahrs.pitch(), ahrs.yaw(), q.w(), q.x(), q.y(), q.z(), b.x(), b.y(), b.z(),
                  ahrs.last_mag_rejected() ? 1 : 0, ahrs.last_acc_rejected() ? 1 : 0, ahrs.still() ? 1 : 0);
    out.write(line);
    ++n;
    if (!truth.t.empty() && t >= truth.t.front() && t <= truth.t.back()) {
      const std::size_t i = nearest(truth.t, t);
      if (n_cmp == 0) {
        yaw0_est = ahrs.yaw();
        yaw0_true = truth.yaw[i];
        p0 = {truth.x[i], truth.y[i]};
        pdr.set_position(p0);
      }
      const double er = wrap(ahrs.roll() - truth.roll[i]), ep = wrap(ahrs.pitch() - truth.pitch[i]);
      // Without a magnetometer the heading is relative to the start.
      yaw_err_end = a.no_mag || !s.has_mag ? wrap((ahrs.yaw() - yaw0_est) - (truth.yaw[i] - yaw0_true))
                                           : wrap(ahrs.yaw() - truth.yaw[i]);
      se_roll += er * er;
      se_pitch += ep * ep;
      se_yaw += yaw_err_end * yaw_err_end;
      yaw_abs_err.push_back(std::abs(yaw_err_end));
      ++n_cmp;
    }
    if (want_steps || !truth.t.empty()) {
      pdr.update(s, ahrs.R_BtoW());
      while (const std::optional<Step> st = pdr.pop_step()) {
        step_times.push_back(ns_to_seconds(st->t));
        if (steps_out) {
          std::snprintf(line, sizeof line, "%.6f,%.4f,%.5f,%.4f,%.4f\n", ns_to_seconds(st->t), st->length_m,
                        st->heading_rad, pdr.position().x(), pdr.position().y());
          steps_out->write(line);
        }
      }
    }
    if (a.duration_s > 0.0 && ns_to_seconds(s.t - *t_first) >= a.duration_s) break;
  }
  pdr.finish();
  while (const std::optional<Step> st = pdr.pop_step()) {
    step_times.push_back(ns_to_seconds(st->t));
    if (steps_out) {
      std::snprintf(line, sizeof line, "%.6f,%.4f,%.5f,%.4f,%.4f\n", ns_to_seconds(st->t), st->length_m,
                    st->heading_rad, pdr.position().x(), pdr.position().y());
      steps_out->write(line);
    }
  }
  std::signal(SIGINT, old_int);
  std::signal(SIGTERM, old_term);
  g_live.store(nullptr);
  out.flush();
  if (steps_out) steps_out->flush();

  // Summary: to stderr when the attitude goes to stdout.
  std::FILE* info = out.is_stdout() ? stderr : stdout;
  constexpr double kDeg = 180.0 / std::numbers::pi;
  const AhrsRejections& rj = ahrs.rejections();
  std::fprintf(info, "imu: %llu samples from %s -> %s (gyro bias %.4f %.4f %.4f deg/s, %llu magnetometer samples rejected)\n",
               static_cast<unsigned long long>(n), source->name().c_str(), a.out.c_str(), ahrs.gyro_bias().x() * kDeg,
               ahrs.gyro_bias().y() * kDeg, ahrs.gyro_bias().z() * kDeg,
               static_cast<unsigned long long>(rj.mag_samples));
  // What the filter refused, always on stderr (the attitude may be on stdout).
  std::fprintf(stderr,
               "imu: rejected magnetometer %llu samples (%.1f s: magnitude %llu, dip %llu, heading %llu; %llu lasting "
               "fields adopted), accelerometer %llu samples (%.1f s, off g)\n",
               static_cast<unsigned long long>(rj.mag_samples), rj.mag_s,
               static_cast<unsigned long long>(rj.mag_magnitude), static_cast<unsigned long long>(rj.mag_dip),
               static_cast<unsigned long long>(rj.mag_heading), static_cast<unsigned long long>(rj.mag_adopted),
               static_cast<unsigned long long>(rj.acc_samples), rj.acc_s);
  for (const auto& [reason, e] : source->drops().snapshot())
    std::fprintf(info, "imu: dropped %llu (%s), first: %s\n", static_cast<unsigned long long>(e.count),
                 reason.c_str(), e.first_message.c_str());
  if (const double gyro_absent_s = pdr.gyro_absent_s(); gyro_absent_s > 0.0)
    std::fprintf(info,
                 "imu: no gyroscope for %.1f s (gx, gy, gz exactly 0): steps took the vertical from the "
                 "accelerometer's %.0f s mean; the attitude's yaw is not observed there\n",
                 gyro_absent_s, pdr.options().gravity_window.window_s);
  if (want_steps || !truth.t.empty())
    std::fprintf(info, "pdr: %llu steps, %.2f m walked, end at (%.2f, %.2f); %llu samples of heel-strike impacts replaced\n",
                 static_cast<unsigned long long>(pdr.step_count()), pdr.distance_m(), pdr.position().x(),
                 pdr.position().y(), static_cast<unsigned long long>(pdr.impact_samples()));
  if (n_cmp > 0) {
    constexpr double deg = 180.0 / std::numbers::pi;
    const double nn = static_cast<double>(n_cmp);
    std::fprintf(info,
                 "truth: roll rms %.3f deg, pitch rms %.3f deg, yaw rms %.3f deg, yaw error at the end %.3f deg%s\n",
                 std::sqrt(se_roll / nn) * deg, std::sqrt(se_pitch / nn) * deg, std::sqrt(se_yaw / nn) * deg,
                 yaw_err_end * deg, a.no_mag ? " (heading relative to the start: no magnetometer)" : "");
    // Percentiles of |yaw error| over every compared sample (nearest rank).
    std::sort(yaw_abs_err.begin(), yaw_abs_err.end());
    const auto pct = [&](double p) {
      const std::size_t k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(yaw_abs_err.size())));
      return yaw_abs_err[std::clamp<std::size_t>(k, 1, yaw_abs_err.size()) - 1] * deg;
    };
    std::fprintf(info, "truth: yaw error p50 %.3f deg, p95 %.3f deg, max %.3f deg\n", pct(0.50), pct(0.95),
                 yaw_abs_err.back() * deg);
    // Distance walked by the truth and the PDR end-point error.
    double walked = 0.0;
    for (std::size_t i = 1; i < truth.t.size(); ++i)
      walked += std::hypot(truth.x[i] - truth.x[i - 1], truth.y[i] - truth.y[i - 1]);
    const std::size_t last = truth.t.size() - 1;
    const double end_err = std::hypot(pdr.position().x() - truth.x[last], pdr.position().y() - truth.y[last]);
    std::fprintf(info, "truth: walked %.2f m; PDR end point %.2f m from the true end (%.2f %% of the distance)\n",
                 walked, end_err, walked > 0 ? 100.0 * end_err / walked : 0.0);
    const fs::path steps_csv = fs::path(a.truth).parent_path() / "steps.csv";
    if (fs::exists(steps_csv)) {
      const StepMatch m = match_steps(step_times, read_step_times(steps_csv.string()));
      std::fprintf(info, "truth: %zu of %zu steps found (%.1f %%), %zu false (%.1f %%), max offset %.3f s\n",
                   m.matched, m.truth, 100.0 * m.recall(), m.false_steps(), 100.0 * m.false_rate(), m.max_offset_s);
    }
  }
  std::fflush(info);
  if (const std::string f = source->failure(); !f.empty()) {
    std::fprintf(stderr, "luxloc: runtime failure: %s\n", f.c_str());
    return 1;
  }
  return 0;
}

}  // namespace

void add_imu_command(CLI::App& root, Action& action) {
  auto args = std::make_shared<ImuArgs>();
  CLI::App* cmd = root.add_subcommand(
      "imu", "attitude and heading reference (Mahony, SEEDS.md C): one row t,roll,pitch,yaw,qw,qx,qy,qz per IMU sample, then "
      "bias_gx,bias_gy,bias_gz,mag_rejected,acc_rejected,still");
  auto* in = cmd->add_option("--in", args->in, "IMU log in SPEC imu.csv form, or a session folder holding imu.csv")
                 ->check(CLI::ExistingPath);
  auto* src = cmd->add_option("--source", args->source,
                              "live IMU instead of --in: serial-imu:/dev/ttyX[,baud=..,protocol=csv|witmotion,...]");
  in->excludes(src);
  cmd->add_option("--out", args->out, "attitude CSV to write ('-' = stdout)")->required();
  cmd->add_option("--imu-calib", args->imu_calib, "IMU calibration YAML from `luxloc calib imu`")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--no-mag", args->no_mag, "ignore the magnetometer (yaw starts at 0 and is relative)");
  cmd->add_option("--kp", args->kp, "Mahony proportional gain")->check(CLI::NonNegativeNumber)->capture_default_str();
  cmd->add_option("--ki", args->ki, "Mahony integral gain")->check(CLI::NonNegativeNumber)->capture_default_str();
  cmd->add_option("--kp-heading", args->kp_heading, "proportional gain of the magnetometer's heading error")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--ki-heading", args->ki_heading, "integral gain of the heading error (gyro bias about the vertical)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--mag-gate", args->mag_gate_deg, "heading innovation (deg) beyond which the field is a disturbance")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--mag-rejection", args->mag_rejection, "field magnitude change (fraction) rejected as a disturbance")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--no-bias-at-rest", args->no_bias_at_rest,
                "do not take the mean rate at standstills as the gyro bias (only the magnetometer learns it)");
  cmd->add_flag("--no-still-mag-turn", args->no_still_mag_turn,
                "the standstill test does not ask the magnetometer whether the device turns slowly (for comparisons)");
  cmd->add_flag("--no-impact-filter", args->no_impact_filter,
                "steps: keep heel-strike impacts in the vertical acceleration (core/imu/impact_filter.hpp; for "
                "comparisons)");
  cmd->add_option("--steps", args->steps, "also run pedestrian dead reckoning; write t,length_m,heading_rad,x,y per step");
  cmd->add_option("--step-model", args->step_model, "step-length model")
      ->check(CLI::IsMember({"weinberg", "cadence", "constant"}))
      ->capture_default_str();
  cmd->add_option("--truth", args->truth,
                  "groundtruth.csv with yaw,roll,pitch (the simulator's): print attitude errors, the PDR end-point "
                  "error and, with steps.csv beside it, step detection scores")
      ->check(CLI::ExistingFile);
  cmd->add_option("--duration", args->duration_s, "stop after this many seconds of data (live sources)")
      ->check(CLI::PositiveNumber);
  cmd->footer(
      "Angles in radians (roll, pitch, yaw: ZYX Euler, yaw CCW from east). Live samples are stamped on arrival with "
      "CLOCK_MONOTONIC (seconds since boot). Exit 1 when a live device is lost, 2 on bad input.");
  cmd->callback([&action, args] {
    if (args->in.empty() && args->source.empty()) throw CLI::RequiredError("--in or --source");
    action = [args] { return run_imu(*args); };
  });
}

}  // namespace luxloc::app
