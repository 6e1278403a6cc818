#include "plugins/external/external_plugin.hpp"

#include <dlfcn.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <opencv2/core.hpp>

#include "core/common/input_error.hpp"

namespace luxloc {
namespace {

std::mutex g_mutex;
std::vector<std::shared_ptr<const ExternalPlugin>> g_plugins;

PluginSource* self(void* ctx) { return static_cast<PluginSource*>(ctx); }

int push_imu(void* ctx, const luxloc_imu_sample* s) {
  if (!s) return self(ctx)->refuse("imu: null sample");
  ImuSample m;
  m.t = s->t_ns;
  m.acc_inB = {s->acc[0], s->acc[1], s->acc[2]};
  m.gyro_inB = {s->gyro[0], s->gyro[1], s->gyro[2]};
  m.has_mag = s->has_mag != 0;
  if (m.has_mag) m.mag_inB = {s->mag[0], s->mag[1], s->mag[2]};
  if (!m.acc_inB.allFinite() || !m.gyro_inB.allFinite() || (m.has_mag && !m.mag_inB.allFinite()))
    return self(ctx)->refuse("imu: non-finite value");
  return self(ctx)->take(m);
}

int push_frame(void* ctx, const luxloc_frame_sample* s) {
  if (!s || !s->gray || s->width <= 0 || s->height <= 0 || s->stride < s->width)
    return self(ctx)->refuse("frame: no pixels or a bad size/stride");
  FrameSample f;
  f.t = s->t_ns;
  // Copied: the plugin keeps its buffer.
  f.gray = cv::Mat(s->height, s->width, CV_8UC1, const_cast<uint8_t*>(s->gray), static_cast<std::size_t>(s->stride))
               .clone();
  return self(ctx)->take(std::move(f));
}

int push_fix(void* ctx, const luxloc_fix_sample* s) {
  if (!s || !std::isfinite(s->x) || !std::isfinite(s->y)) return self(ctx)->refuse("fix: non-finite position");
  FixSample f;
  f.t = s->t_ns;
  f.p_inW = {s->x, s->y};
  f.sigma_m = std::isfinite(s->sigma_m) && s->sigma_m > 0 ? s->sigma_m : std::nan("");
  return self(ctx)->take(f);
}

int push_uwb(void* ctx, const luxloc_uwb_sample* s) {
  if (!s || !std::isfinite(s->range_m)) return self(ctx)->refuse("uwb: non-finite range");
  UwbSample u;
  u.t = s->t_ns;
  u.anchor = s->anchor;
  u.range_m = s->range_m;
  u.aoa_rad = s->aoa_rad;
  return self(ctx)->take(u);
}

int stop_requested(void* ctx) { return self(ctx)->stopping() ? 1 : 0; }

}  // namespace

std::shared_ptr<const ExternalPlugin> ExternalPlugin::load(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, 0, "--plugin", "no such plugin file");
  std::shared_ptr<ExternalPlugin> p(new ExternalPlugin());  // private constructor
  p->path_ = path;
  p->library_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!p->library_) throw InputError(path, 0, "--plugin", std::string("cannot load: ") + dlerror());
  dlerror();
  void* sym = dlsym(p->library_, "luxloc_plugin_entry");
  if (!sym)
    throw InputError(path, 0, "--plugin",
                     "no symbol luxloc_plugin_entry: not a luxloc plugin (see plugins/abi/luxloc_plugin.h)");
  const auto entry = reinterpret_cast<luxloc_plugin_entry_fn>(sym);
  p->descriptor_ = entry(LUXLOC_PLUGIN_ABI_VERSION);
  if (!p->descriptor_)
    throw InputError(path, 0, "--plugin",
                     "the plugin declined ABI version " + std::to_string(LUXLOC_PLUGIN_ABI_VERSION));
  if (p->descriptor_->abi_version != LUXLOC_PLUGIN_ABI_VERSION)
    throw InputError(path, 0, "--plugin",
                     "plugin ABI version " + std::to_string(p->descriptor_->abi_version) + ", this luxloc speaks " +
                         std::to_string(LUXLOC_PLUGIN_ABI_VERSION) + ": rebuild the plugin against this luxloc");
  const luxloc_source_plugin& d = *p->descriptor_;
  if (!d.kind || !*d.kind || !d.open || !d.next || !d.close)
    throw InputError(path, 0, "--plugin", "incomplete descriptor (kind, open, next and close are required)");
  return p;
}

ExternalPlugin::~ExternalPlugin() {
  if (library_) dlclose(library_);
}

PluginSource::PluginSource(std::shared_ptr<const ExternalPlugin> plugin, const SourceSpec& spec)
    : plugin_(std::move(plugin)), name_(spec.kind + ":" + spec.target), limits_(spec.limits()) {
  const std::size_t comma = spec.text.find(',');
  const std::string params = comma == std::string::npos ? "" : spec.text.substr(comma + 1);
  char err[512] = {0};
  handle_ = plugin_->descriptor().open(spec.target.c_str(), params.c_str(), err, sizeof err);
  if (!handle_)
    throw InputError("--source", 0, spec.text, std::string(err[0] ? err : "the plugin refused to open the source"));
  host_.abi_version = LUXLOC_PLUGIN_ABI_VERSION;
  host_.ctx = this;
  host_.push_imu = push_imu;
  host_.push_frame = push_frame;
  host_.push_fix = push_fix;
  host_.push_uwb = push_uwb;
  host_.stop_requested = stop_requested;
}

PluginSource::~PluginSource() {
  if (handle_) plugin_->descriptor().close(handle_);
}

int PluginSource::take(SensorData d) {
  if (!admit_plausible(d, limits_, drops(), name_)) return 1;
  staged_.push_back(std::move(d));
  return 0;
}

int PluginSource::refuse(const std::string& why) {
  drops().add("bad sample", name_ + ": " + why);
  return 1;
}

bool PluginSource::next(SensorData& out) {
  while (staged_.empty()) {
    if (ended_ || stop_) return false;
    char err[512] = {0};
    const int r = plugin_->descriptor().next(handle_, &host_, err, sizeof err);
    if (r == LUXLOC_NEXT_END) {
      ended_ = true;
    } else if (r != LUXLOC_NEXT_MORE) {
      ended_ = true;
      failure_ = std::string(err[0] ? err : "the plugin reported a failure");
    }
  }
  out = std::move(staged_.front());
  staged_.pop_front();
  return true;
}

void register_external_plugin(const std::string& path) {
  std::lock_guard lock(g_mutex);
  for (const auto& p : g_plugins)
    if (p->path() == path) return;
  auto p = ExternalPlugin::load(path);
  for (const auto& q : g_plugins)
    if (q->kind() == p->kind())
      throw InputError(path, 0, "--plugin", "source kind '" + p->kind() + "' is provided by " + q->path() + " already");
  g_plugins.push_back(std::move(p));
}

std::vector<std::shared_ptr<const ExternalPlugin>> external_plugins() {
  std::lock_guard lock(g_mutex);
  return g_plugins;
}

SourcePtr make_external_source(const SourceSpec& spec) {
  for (const auto& p : external_plugins())
    if (p->kind() == spec.kind) return std::make_unique<PluginSource>(p, spec);
  return nullptr;
}

}  // namespace luxloc
