#include "plugins/uwb/uwb_serial_source.hpp"


#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "core/common/input_error.hpp"
#include "plugins/uwb/tof_aoa_line_parser.hpp"

namespace luxloc {

UwbSerialOptions UwbSerialOptions::from_spec(const SourceSpec& spec) {
  UwbSerialOptions o;
  o.path = spec.target;
  const double baud = spec.get_number("baud", 115200);
  if (baud != static_cast<int>(baud) || !SerialPort::is_standard_baud(static_cast<int>(baud)))
    throw InputError("--source", 0, "baud", "'" + spec.text + "': not a standard baud rate");
  o.baud = static_cast<int>(baud);
  const std::string protocol = spec.get("protocol", "dwm1001");
  if (protocol == "dwm1001")
    o.protocol = UwbProtocol::dwm1001;
  else if (protocol == "tof-aoa")
    o.protocol = UwbProtocol::tof_aoa;
  else
    throw InputError("--source", 0, "protocol", "'" + spec.text + "': protocol must be dwm1001 or tof-aoa");
  const std::string on_loss = spec.get("on_loss", "end");
  if (on_loss != "end" && on_loss != "wait")
    throw InputError("--source", 0, "on_loss", "'" + spec.text + "': on_loss must be end or wait");
  o.on_loss = on_loss == "wait" ? OnLoss::wait : OnLoss::end;
  const std::string init = spec.get("init", "none");
  if (init != "none" && init != "lec")
    throw InputError("--source", 0, "init", "'" + spec.text + "': init must be none or lec");
  o.init_lec = init == "lec";
  const std::string position = spec.get("position", "0");
  if (position != "0" && position != "1")
    throw InputError("--source", 0, "position", "'" + spec.text + "': position must be 0 or 1");
  o.dwm1001.emit_position = position == "1";
  const double q = spec.get_number("min_quality", o.dwm1001.min_quality);
  if (!(q >= 0 && q <= 100)) throw InputError("--source", 0, "min_quality", "'" + spec.text + "': 0..100");
  o.dwm1001.min_quality = static_cast<int>(q);
  o.limits = spec.limits();
  static const char* known[] = {"baud", "protocol", "on_loss", "init", "position", "min_quality"};
  for (const auto& [key, value] : spec.params) {
    bool ok = false;
    for (const char* k : known) ok = ok || key == k;
    for (const auto& k : SourceSpec::limit_keys()) ok = ok || key == k;
    if (!ok) throw InputError("--source", 0, key, "'" + spec.text + "': unknown option for uwb");
  }
  return o;
}

UwbSerialSource::UwbSerialSource(UwbSerialOptions options)
    : options_(std::move(options)), stream_(options_.stream(), name(), drops()) {
  parser_ = make_parser();
  send_init();
}

std::unique_ptr<UwbStreamParser> UwbSerialSource::make_parser() {
  if (options_.protocol == UwbProtocol::tof_aoa) return std::make_unique<TofAoaLineParser>(drops());
  return std::make_unique<Dwm1001Parser>(drops(), options_.dwm1001);
}

void UwbSerialSource::send_init() {
  SerialPort* port = stream_.port();
  if (!options_.init_lec || !port) return;
  // The DWM1001 enters its shell on two carriage returns within a second; it needs a
  // moment before it takes a command.
  static const std::uint8_t enter[] = {'\r', '\r'};
  static const std::uint8_t lec[] = {'l', 'e', 'c', '\r'};
  port->write_all(enter, sizeof enter);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  port->write_all(lec, sizeof lec);
}

void UwbSerialSource::request_stop() { stream_.request_stop(); }

std::string UwbSerialSource::failure() const { return stream_.failure(); }

bool UwbSerialSource::next(SensorData& out) {
  while (true) {
    if (stream_.stopping()) return false;
    if (!ready_.empty()) {
      out = std::move(ready_.front());
      ready_.pop_front();
      ++samples_;
      return true;
    }
    if (!stream_.read([this] {
          parser_->reset();
          send_init();
        }))
      return false;
    parsed_.clear();
    parser_->feed(stream_.bytes(), stream_.size(), stream_.arrival(), stream_.byte_ns(), parsed_);
    for (SensorData& d : parsed_) {
      if (!admit_plausible(d, options_.limits, drops(), name())) continue;
      // Never decreasing (the ranges of one line share its time).
      std::visit([this](auto& s) {
        if (s.t < last_t_) s.t = last_t_;
        last_t_ = s.t;
      }, d);
      ready_.push_back(std::move(d));
    }
  }
}

SourcePtr make_uwb_serial_source(const SourceSpec& spec) {
  return std::make_unique<UwbSerialSource>(UwbSerialOptions::from_spec(spec));
}

}  // namespace luxloc
