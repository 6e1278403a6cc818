// `luxloc devices`: the cameras (V4L2) and serial ports this machine has, with what VLC
// set-up needs to know: formats, frame sizes and rates, the exposure controls (names, range
// in 100 us units) and the gain, and a --source spec to start from. Exit 0 even when
// nothing is found (it says so).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <linux/videodev2.h>

#include "app/commands.hpp"
#include "plugins/v4l2/exposure_control.hpp"
#include "plugins/v4l2/pixel_format.hpp"
#include "plugins/v4l2/v4l2_device_info.hpp"

namespace luxloc::app {
namespace {

namespace fs = std::filesystem;

struct DevicesArgs {
  std::string dev_dir = "/dev";
};

std::string rates_text(const std::vector<double>& fps) {
  std::string s;
  char buf[32];
  for (double f : fps) {
    std::snprintf(buf, sizeof buf, "%s%g", s.empty() ? "" : " ", f);
    s += buf;
  }
  return s;
}

const V4l2Control* find_control(const V4l2DeviceInfo& d, std::uint32_t id, bool (*by_name)(std::string_view)) {
  for (const V4l2Control& c : d.controls)
    if (c.id == id || (by_name && by_name(c.name))) return &c;
  return nullptr;
}

void print_control(const char* label, const V4l2Control* c, const char* unit_note) {
  if (!c) {
    std::printf("    %-22s none\n", label);
    return;
  }
  std::printf("    %-22s %s: %d..%d step %d, default %d", label, c->ctl_name.c_str(), c->range.minimum,
              c->range.maximum, c->range.step, c->range.default_value);
  if (c->readable) std::printf(", now %d", c->value);
  if (c->inactive) std::printf(" (inactive)");
  if (unit_note) std::printf("%s", unit_note);
  std::printf("\n");
  for (const auto& [index, name] : c->menu) std::printf("    %-22s   %d = %s\n", "", index, name.c_str());
}

void print_camera(const V4l2DeviceInfo& d) {
  if (!d.error.empty()) {
    std::printf("  %s: cannot query: %s\n", d.path.c_str(), d.error.c_str());
    return;
  }
  std::printf("  %s: %s (driver %s, %s)%s\n", d.path.c_str(), d.card.c_str(), d.driver.c_str(), d.bus.c_str(),
              d.capture ? "" : " - not a capture device (metadata or output node)");
  if (!d.capture) return;
  const V4l2FrameSize* best = nullptr;
  std::uint32_t best_fourcc = 0;
  for (const V4l2FormatInfo& f : d.formats) {
    if (f.emulated) continue;
    std::printf("    format %s (%s)%s\n", fourcc_text(f.fourcc).c_str(), f.description.c_str(),
                pixel_format_from_fourcc(f.fourcc) ? "" : " - not used by luxloc");
    for (const V4l2FrameSize& s : f.sizes) {
      if (s.stepwise)
        std::printf("      %dx%d .. %dx%d (any size in between)\n", s.min_width, s.min_height, s.width, s.height);
      else
        std::printf("      %dx%d%s%s\n", s.width, s.height, s.fps.empty() ? "" : " @ ", rates_text(s.fps).c_str());
      // Suggest the largest mode in luxloc's preferred format order at >= 30 fps.
      const auto fmt = pixel_format_from_fourcc(f.fourcc);
      const bool fast = s.fps.empty() || *std::max_element(s.fps.begin(), s.fps.end()) >= 29.9;
      if (fmt && fast && (!best || (best_fourcc == f.fourcc && s.width * s.height > best->width * best->height))) {
        best = &s;
        best_fourcc = f.fourcc;
      }
    }
  }
  const V4l2Control* ae = find_control(d, V4L2_CID_EXPOSURE_AUTO, &is_auto_exposure_name);
  const V4l2Control* abs = find_control(d, V4L2_CID_EXPOSURE_ABSOLUTE, &is_exposure_absolute_name);
  const V4l2Control* dyn = find_control(d, V4L2_CID_EXPOSURE_AUTO_PRIORITY, &is_exposure_dynamic_framerate_name);
  const V4l2Control* gain = find_control(d, V4L2_CID_GAIN, nullptr);
  print_control("auto exposure", ae, nullptr);
  std::string note;
  if (abs) {
    char buf[96];
    std::snprintf(buf, sizeof buf, " (x 100 us: %.0f..%.0f us)", exposure_units_to_us(abs->range.minimum),
                  exposure_units_to_us(abs->range.maximum));
    note = buf;
  }
  print_control("exposure", abs, abs ? note.c_str() : nullptr);
  print_control("dynamic frame rate", dyn, nullptr);
  print_control("gain", gain, nullptr);
  if (!abs)
    std::printf("    no manual exposure control: this camera cannot take the short exposures stripes need\n");
  if (best) {
    const double exposure = abs ? std::max(100.0, exposure_units_to_us(abs->range.minimum)) : 0.0;
    std::printf("    try: --source v4l2:%s,width=%d,height=%d,fps=30,format=%s%s\n", d.path.c_str(), best->width,
                best->height, pixel_format_name(*pixel_format_from_fourcc(best_fourcc)).c_str(),
                abs ? (",exposure_us=" + std::to_string(static_cast<int>(exposure))).c_str() : ",exposure_us=auto");
  }
}

std::vector<std::string> serial_ports(const fs::path& dev) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dev, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("ttyUSB", 0) == 0 || name.rfind("ttyACM", 0) == 0) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  for (const auto& e : fs::directory_iterator(dev / "serial" / "by-id", ec)) {
    std::error_code ec2;
    const fs::path target = fs::canonical(e.path(), ec2);
    out.push_back(e.path().string() + (ec2 ? "" : " -> " + target.string()));
  }
  return out;
}

int run_devices(const DevicesArgs& a) {
  const std::vector<std::string> video = v4l2_device_paths(a.dev_dir);
  std::printf("Cameras (V4L2, %s/video*):\n", a.dev_dir.c_str());
  if (video.empty()) std::printf("  no camera found (no %s/video* device)\n", a.dev_dir.c_str());
  int capture = 0;
  for (const std::string& p : video) {
    const V4l2DeviceInfo info = query_v4l2_device(p);
    capture += info.capture ? 1 : 0;
    print_camera(info);
  }
  if (!video.empty() && capture == 0) std::printf("  no camera found (no capture device among them)\n");

  const std::vector<std::string> serial = serial_ports(a.dev_dir);
  std::printf("Serial ports (%s/ttyUSB*, %s/ttyACM*, %s/serial/by-id/*):\n", a.dev_dir.c_str(), a.dev_dir.c_str(),
              a.dev_dir.c_str());
  if (serial.empty()) std::printf("  no serial port found\n");
  for (const std::string& s : serial) std::printf("  %s\n", s.c_str());
  std::fflush(stdout);
  return 0;
}

}  // namespace

void add_devices_command(CLI::App& root, Action& action) {
  auto args = std::make_shared<DevicesArgs>();
  CLI::App* cmd = root.add_subcommand("devices", "list V4L2 cameras (formats, sizes, exposure controls) and serial ports");
  cmd->add_option("--dev-dir", args->dev_dir, "device folder to scan")->capture_default_str();
  cmd->callback([args, &action] { action = [args] { return run_devices(*args); }; });
}

}  // namespace luxloc::app
