#include "plugins/serial/serial_imu_source.hpp"


#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "core/common/input_error.hpp"

namespace luxloc {
namespace {

constexpr TimeNs kMinStep = 1000;  // 1 us between consecutive stamps at least

// Runs f, turning std::invalid_argument into InputError on the --source field `key`.
template <class F>
auto spec_value(const SourceSpec& spec, const std::string& key, F f) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw InputError("--source", 0, key, "'" + spec.text + "': " + e.what());
  }
}

}  // namespace

SerialImuOptions SerialImuOptions::from_spec(const SourceSpec& spec) {
  SerialImuOptions o;
  o.path = spec.target;
  const double baud = spec.get_number("baud", 115200);
  if (baud != static_cast<int>(baud) || !SerialPort::is_standard_baud(static_cast<int>(baud))) {
    std::string list;
    for (int b : SerialPort::standard_bauds()) {
      if (!list.empty()) list.append(" ");
      list.append(std::to_string(b));
    }
    throw InputError("--source", 0, "baud", "'" + spec.text + "': not a standard baud rate (" + list + ")");
  }
  o.baud = static_cast<int>(baud);
  const std::string protocol = spec.get("protocol", "csv");
  if (protocol == "csv")
    o.protocol = SerialProtocol::csv;
  else if (protocol == "witmotion")
    o.protocol = SerialProtocol::witmotion;
  else
    throw InputError("--source", 0, "protocol", "'" + spec.text + "': protocol must be csv or witmotion");
  const std::string on_loss = spec.get("on_loss", "end");
  if (on_loss == "end")
    o.on_loss = OnLoss::end;
  else if (on_loss == "wait")
    o.on_loss = OnLoss::wait;
  else
    throw InputError("--source", 0, "on_loss", "'" + spec.text + "': on_loss must be end or wait");
  o.axes = spec_value(spec, "axes", [&] { return ImuAxisMap::parse(spec.get("axes", "+x+y+z")); });

  o.witmotion.acc_range_g = spec.get_number("acc_range_g", o.witmotion.acc_range_g);
  o.witmotion.gyro_range_dps = spec.get_number("gyro_range_dps", o.witmotion.gyro_range_dps);
  o.witmotion.mag_scale_ut = spec.get_number("mag_scale", o.witmotion.mag_scale_ut);
  if (!(o.witmotion.acc_range_g > 0) || !(o.witmotion.gyro_range_dps > 0) || o.witmotion.mag_scale_ut == 0.0)
    throw InputError("--source", 0, "acc_range_g", "'" + spec.text + "': ranges and scales must be > 0");

  if (spec.params.count("columns"))
    o.csv.columns = spec_value(spec, "columns", [&] { return CsvLineOptions::parse_columns(spec.get("columns", "")); });
  o.csv.acc_to_mps2 = spec_value(spec, "acc_unit", [&] { return CsvLineOptions::acc_unit(spec.get("acc_unit", "mps2")); });
  o.csv.gyro_to_rps = spec_value(spec, "gyro_unit", [&] { return CsvLineOptions::gyro_unit(spec.get("gyro_unit", "rps")); });
  o.csv.mag_to_ut = spec_value(spec, "mag_unit", [&] { return CsvLineOptions::mag_unit(spec.get("mag_unit", "ut")); });
  o.csv.time_to_s = spec_value(spec, "time_unit", [&] { return CsvLineOptions::time_unit(spec.get("time_unit", "s")); });
  const std::string time = spec.get("time", "arrival");
  if (time != "arrival" && time != "device")
    throw InputError("--source", 0, "time", "'" + spec.text + "': time must be arrival or device");
  o.csv.device_time = time == "device";

  // Plausible ranges: the device's declared full scale where it has one (WitMotion), else
  // the defaults; acc_max_g= / gyro_max_dps= override either.
  SensorLimits declared;
  if (o.protocol == SerialProtocol::witmotion) {
    declared.acc_max_mps2 = o.witmotion.acc_range_g * SensorLimits::kStandardGravity;
    declared.gyro_max_rad_s = o.witmotion.gyro_range_dps * 3.141592653589793 / 180.0;
  }
  o.limits = spec.limits(declared);

  static const char* known[] = {"baud", "protocol", "on_loss", "axes", "acc_range_g", "gyro_range_dps", "mag_scale",
                                "columns", "acc_unit", "gyro_unit", "mag_unit", "time", "time_unit"};
  for (const auto& [key, value] : spec.params) {
    bool ok = false;
    for (const char* k : known) ok = ok || key == k;
    for (const auto& k : SourceSpec::limit_keys()) ok = ok || key == k;
    if (!ok) throw InputError("--source", 0, key, "'" + spec.text + "': unknown option for serial-imu");
  }
  return o;
}

SerialStreamOptions SerialImuOptions::stream() const {
  return {path, baud, on_loss, reopen_interval_s, poll_timeout_ms, report_to_stderr};
}

SerialImuSource::SerialImuSource(SerialImuOptions options)
    : options_(std::move(options)), stream_(options_.stream(), name(), drops()) {
  parser_ = make_parser();
}

std::unique_ptr<ImuStreamParser> SerialImuSource::make_parser() {
  if (options_.protocol == SerialProtocol::witmotion) return std::make_unique<WitMotionParser>(drops(), options_.witmotion);
  return std::make_unique<CsvLineParser>(drops(), options_.csv);
}

void SerialImuSource::request_stop() { stream_.request_stop(); }

std::string SerialImuSource::failure() const { return stream_.failure(); }

bool SerialImuSource::next(SensorData& out) {
  while (true) {
    if (stream_.stopping()) return false;
    if (!ready_.empty()) {
      out = ready_.front();
      ready_.pop_front();
      ++samples_;
      return true;
    }
    if (!stream_.read([this] { parser_->reset(); })) return false;
    bytes_ += stream_.size();
    parsed_.clear();
    parser_->feed(stream_.bytes(), stream_.size(), stream_.arrival(), stream_.byte_ns(), parsed_);
    for (ImuSample& s : parsed_) {
      if (s.t < last_t_ + kMinStep) {
        s.t = last_t_ + kMinStep;
        ++retimed_;
      }
      last_t_ = s.t;
      const ImuSample body = options_.axes.identity() ? s : options_.axes.apply(s);
      if (admit_plausible(body, options_.limits, drops(), name())) ready_.push_back(body);
    }
  }
}

SourcePtr make_serial_imu_source(const SourceSpec& spec) {
  return std::make_unique<SerialImuSource>(SerialImuOptions::from_spec(spec));
}

}  // namespace luxloc
