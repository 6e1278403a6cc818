#pragma once
// External source plugins through the versioned C ABI (plugins/abi/luxloc_plugin.h):
// `--plugin PATH.so` loads the library (dlopen), checks its entry point and ABI version,
// and registers the source kind it provides; `--source KIND:...` then opens a PluginSource.
// The host owns the thread (the pipeline's source thread calls the plugin's next()) and the
// queue (samples pushed during a call are staged, checked and handed out one by one).
#include <atomic>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "core/pipeline/source.hpp"
#include "plugins/abi/luxloc_plugin.h"
#include "plugins/source_spec.hpp"

namespace luxloc {

// A loaded plugin library; dlclose()d when the last user is gone.
class ExternalPlugin {
 public:
  // Throws InputError naming the path: file missing, not loadable, no luxloc_plugin_entry,
  // no descriptor, ABI version mismatch, incomplete descriptor.
  static std::shared_ptr<const ExternalPlugin> load(const std::string& path);
  ~ExternalPlugin();
  ExternalPlugin(const ExternalPlugin&) = delete;
  ExternalPlugin& operator=(const ExternalPlugin&) = delete;

  const std::string& path() const { return path_; }
  std::string kind() const { return descriptor_->kind; }
  std::string description() const { return descriptor_->description ? descriptor_->description : ""; }
  const luxloc_source_plugin& descriptor() const { return *descriptor_; }

 private:
  ExternalPlugin() = default;
  std::string path_;
  void* library_ = nullptr;
  const luxloc_source_plugin* descriptor_ = nullptr;
};

class PluginSource final : public Source {
 public:
  // Opens the plugin's source; throws InputError with the plugin's message when it refuses.
  PluginSource(std::shared_ptr<const ExternalPlugin> plugin, const SourceSpec& spec);
  ~PluginSource() override;
  std::string name() const override { return name_; }
  bool next(SensorData& out) override;
  void request_stop() override { stop_ = true; }
  bool live() const override { return true; }
  std::string failure() const override { return failure_; }

  // Host callbacks (C ABI): stage a sample / count a refused one; 0 taken, 1 refused.
  int take(SensorData d);
  int refuse(const std::string& why);
  bool stopping() const { return stop_; }

 private:
  std::shared_ptr<const ExternalPlugin> plugin_;
  void* handle_ = nullptr;
  std::string name_;
  luxloc_host host_{};
  std::deque<SensorData> staged_;
  SensorLimits limits_;  // samples beyond them are refused as "out of range"
  bool ended_ = false;
  std::atomic<bool> stop_{false};
  std::string failure_;
};

// Loaded plugins by kind (process-wide: `--plugin` is read once per run).
void register_external_plugin(const std::string& path);
std::vector<std::shared_ptr<const ExternalPlugin>> external_plugins();
// nullptr when no loaded plugin provides spec.kind.
SourcePtr make_external_source(const SourceSpec& spec);

}  // namespace luxloc
