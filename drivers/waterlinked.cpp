#include "drivers/waterlinked.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <utility>

namespace pensight::drivers {

namespace {

using nlohmann::json;

WaterLinkedParse malformed(std::string why) {
  return {WaterLinkedLine::kMalformed, std::nullopt, std::move(why)};
}

WaterLinkedParse report(WaterLinkedReport r) {
  return {WaterLinkedLine::kReport, std::move(r), {}};
}

// Device times are microseconds since the epoch; past kMaxDeviceTimeUs (the year 2262) they do not
// fit the nanoseconds every sample carries, so such a report is malformed.
constexpr int64_t kMaxDeviceTimeUs = std::numeric_limits<int64_t>::max() / 1000;

void check_device_time(const std::optional<int64_t>& us, const char* name, std::string& error) {
  if (us && (*us < 0 || *us > kMaxDeviceTimeUs) && error.empty()) {
    error = std::string("'") + name + "' (" + std::to_string(*us) + " us) is outside 0.." +
            std::to_string(kMaxDeviceTimeUs) + " us";
  }
}

// --- JSON ----------------------------------------------------------------------------------------

// A number member: nullopt when absent or null (older firmware), an error when of another type.
struct JsonReader {
  const json& object;
  std::string error;

  std::optional<double> number(const char* key) {
    const auto it = object.find(key);
    if (it == object.end() || it->is_null()) return std::nullopt;
    if (!it->is_number()) {
      error = std::string("'") + key + "' is not a number";
      return std::nullopt;
    }
    return it->get<double>();
  }
  double required_number(const char* key) {
    const std::optional<double> v = number(key);
    if (!v && error.empty()) error = std::string("'") + key + "' is missing";
    return v.value_or(kNaN);
  }
  std::optional<int64_t> integer(const char* key) {
    const auto it = object.find(key);
    if (it == object.end() || it->is_null()) return std::nullopt;
    if (it->is_number_integer()) return it->get<int64_t>();
    if (it->is_number_float() && std::abs(it->get<double>()) < 9.2e18) {
      return static_cast<int64_t>(std::llround(it->get<double>()));
    }
    error = std::string("'") + key + "' is not an integer";
    return std::nullopt;
  }
  std::optional<bool> boolean(const char* key) {
    const auto it = object.find(key);
    if (it == object.end() || it->is_null()) return std::nullopt;
    if (!it->is_boolean()) {
      error = std::string("'") + key + "' is not true or false";
      return std::nullopt;
    }
    return it->get<bool>();
  }
  std::string string(const char* key) {
    const auto it = object.find(key);
    return it != object.end() && it->is_string() ? it->get<std::string>() : std::string();
  }
};

WaterLinkedParse json_velocity(const json& j, bool water_track) {
  JsonReader r{j, {}};
  WaterLinkedVelocity v;
  v.water_track = water_track || r.string("tracking_mode") == "water";
  v.velocity_mps = {r.required_number("vx"), r.required_number("vy"), r.required_number("vz")};
  const std::optional<bool> valid = r.boolean("velocity_valid");
  if (!valid && r.error.empty()) r.error = "'velocity_valid' is missing";
  v.valid = valid.value_or(false);
  v.fom_mps = r.number("fom").value_or(kNaN);
  v.altitude_m = r.number("altitude").value_or(kNaN);
  v.status = static_cast<int>(r.integer("status").value_or(0));
  v.since_last_report_ms = r.number("time").value_or(kNaN);
  v.time_of_validity_us = r.integer("time_of_validity");
  v.time_of_transmission_us = r.integer("time_of_transmission");
  check_device_time(v.time_of_validity_us, "time_of_validity", r.error);
  check_device_time(v.time_of_transmission_us, "time_of_transmission", r.error);
  v.format = r.string("format");
  if (const auto c = j.find("covariance"); c != j.end() && !c->is_null()) {
    bool ok = c->is_array() && c->size() == 3;
    for (size_t row = 0; ok && row < 3; ++row) {
      const json& cr = (*c)[row];
      ok = cr.is_array() && cr.size() == 3;
      for (size_t col = 0; ok && col < 3; ++col) {
        ok = cr[col].is_number();
        if (ok) v.covariance_m2ps2[3 * row + col] = cr[col].get<double>();
      }
    }
    if (!ok && r.error.empty()) r.error = "'covariance' is not a 3x3 array of numbers";
  }
  if (const auto t = j.find("transducers"); t != j.end() && !t->is_null()) {
    if (!t->is_array()) {
      if (r.error.empty()) r.error = "'transducers' is not an array";
    } else {
      for (const json& b : *t) {
        if (!b.is_object()) {
          if (r.error.empty()) r.error = "a transducer is not an object";
          break;
        }
        JsonReader br{b, {}};
        WaterLinkedBeam beam;
        beam.id = static_cast<int>(br.integer("id").value_or(-1));
        beam.velocity_mps = br.number("velocity").value_or(kNaN);
        beam.distance_m = br.number("distance").value_or(kNaN);
        beam.rssi_dbm = br.number("rssi").value_or(kNaN);
        beam.nsd_dbm = br.number("nsd").value_or(kNaN);
        beam.valid = br.boolean("beam_valid").value_or(false) && beam.distance_m >= 0;
        if (!beam.valid) beam.distance_m = kNaN;
        if (!br.error.empty() && r.error.empty()) r.error = "transducer: " + br.error;
        v.beams.push_back(beam);
      }
    }
  }
  if (!r.error.empty()) return malformed(std::move(r.error));
  return report(std::move(v));
}

WaterLinkedParse json_dead_reckoning(const json& j) {
  JsonReader r{j, {}};
  WaterLinkedDeadReckoning d;
  d.time_s = r.required_number("ts");
  d.position_m = {r.required_number("x"), r.required_number("y"), r.required_number("z")};
  d.std_m = r.number("std").value_or(kNaN);
  d.roll_deg = r.number("roll").value_or(kNaN);
  d.pitch_deg = r.number("pitch").value_or(kNaN);
  d.yaw_deg = r.number("yaw").value_or(kNaN);
  d.status = static_cast<int>(r.integer("status").value_or(0));
  if (!r.error.empty()) return malformed(std::move(r.error));
  return report(d);
}

WaterLinkedParse json_response(const json& j) {
  JsonReader r{j, {}};
  WaterLinkedResponse resp;
  resp.response_to = r.string("response_to");
  resp.success = r.boolean("success").value_or(false);
  resp.error_message = r.string("error_message");
  const auto result = j.find("result");
  resp.result = result == j.end() ? "null" : result->dump();
  if (!r.error.empty()) return malformed(std::move(r.error));
  return report(std::move(resp));
}

// --- serial --------------------------------------------------------------------------------------

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  size_t start = 0;
  for (;;) {
    const size_t end = s.find(sep, start);
    parts.push_back(s.substr(start, end == std::string_view::npos ? end : end - start));
    if (end == std::string_view::npos) return parts;
    start = end + 1;
  }
}

// A decimal number as the DVL prints them ("-0.400", "1e+09", "-1.00"); nullopt otherwise.
std::optional<double> number_field(std::string_view s) {
  if (s.empty()) return std::nullopt;
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

struct SentenceFields {
  std::span<const std::string_view> f;
  std::string error;

  double number(size_t i, const char* name) {
    const std::optional<double> v = number_field(f[i]);
    if (!v && error.empty()) error = std::string(name) + " is not a number";
    return v.value_or(kNaN);
  }
  std::optional<int64_t> integer(size_t i, const char* name) {
    const std::optional<double> v = number_field(f[i]);
    if (!v || *v != std::floor(*v) || std::abs(*v) > 9.2e18) {
      if (error.empty()) error = std::string(name) + " is not an integer";
      return std::nullopt;
    }
    return static_cast<int64_t>(*v);
  }
  bool yes_no(size_t i, const char* name) {
    if (f[i] != "y" && f[i] != "n" && error.empty()) error = std::string(name) + " is not y or n";
    return f[i] == "y";
  }
};

// wrz: vx,vy,vz,valid,altitude,fom,covariance,tov,tot,time,status; wrs the same without altitude.
WaterLinkedParse sentence_velocity(std::span<const std::string_view> f, bool water_track) {
  const size_t expected = water_track ? 10 : 11;
  if (f.size() != expected) {
    return malformed(std::string(water_track ? "wrs" : "wrz") + " has " + std::to_string(f.size()) +
                     " fields, expected " + std::to_string(expected));
  }
  SentenceFields s{f, {}};
  WaterLinkedVelocity v;
  v.water_track = water_track;
  v.velocity_mps = {s.number(0, "vx"), s.number(1, "vy"), s.number(2, "vz")};
  v.valid = s.yes_no(3, "valid");
  size_t i = 4;
  if (!water_track) v.altitude_m = s.number(i++, "altitude");
  v.fom_mps = s.number(i++, "fom");
  const std::vector<std::string_view> cov = split(f[i++], ';');
  if (cov.size() != 9) {
    if (s.error.empty())
      s.error = "covariance has " + std::to_string(cov.size()) + " entries, not 9";
  } else {
    SentenceFields c{cov, {}};
    for (size_t k = 0; k < 9; ++k) v.covariance_m2ps2[k] = c.number(k, "a covariance entry");
    if (s.error.empty()) s.error = c.error;
  }
  v.time_of_validity_us = s.integer(i++, "time_of_validity");
  v.time_of_transmission_us = s.integer(i++, "time_of_transmission");
  check_device_time(v.time_of_validity_us, "time_of_validity", s.error);
  check_device_time(v.time_of_transmission_us, "time_of_transmission", s.error);
  v.since_last_report_ms = s.number(i++, "time");
  v.status = static_cast<int>(s.integer(i, "status").value_or(0));
  if (!s.error.empty()) return malformed(std::move(s.error));
  return report(std::move(v));
}

// wrx (deprecated): time,vx,vy,vz,fom,altitude,valid,status.
WaterLinkedParse sentence_old_velocity(std::span<const std::string_view> f) {
  if (f.size() != 8)
    return malformed("wrx has " + std::to_string(f.size()) + " fields, expected 8");
  SentenceFields s{f, {}};
  WaterLinkedVelocity v;
  v.deprecated_sentence = true;
  v.since_last_report_ms = s.number(0, "time");
  v.velocity_mps = {s.number(1, "vx"), s.number(2, "vy"), s.number(3, "vz")};
  v.fom_mps = s.number(4, "fom");
  v.altitude_m = s.number(5, "altitude");
  v.valid = s.yes_no(6, "valid");
  v.status = static_cast<int>(s.integer(7, "status").value_or(0));
  if (!v.valid) v.altitude_m = kNaN;  // -1.00 on the wire
  if (!s.error.empty()) return malformed(std::move(s.error));
  return report(std::move(v));
}

// wru: id,velocity,distance,rssi,nsd; a distance of -1 is no return.
WaterLinkedParse sentence_beam(std::span<const std::string_view> f) {
  if (f.size() != 5)
    return malformed("wru has " + std::to_string(f.size()) + " fields, expected 5");
  SentenceFields s{f, {}};
  WaterLinkedBeam b;
  const std::optional<int64_t> id = s.integer(0, "id");
  b.velocity_mps = s.number(1, "velocity");
  b.distance_m = s.number(2, "distance");
  b.rssi_dbm = s.number(3, "rssi");
  b.nsd_dbm = s.number(4, "nsd");
  if (id && (*id < 0 || *id >= kWaterLinkedBeams) && s.error.empty()) s.error = "id is not 0-3";
  b.id = static_cast<int>(id.value_or(-1));
  b.valid = b.distance_m >= 0;
  if (!b.valid) b.distance_m = kNaN;
  if (!s.error.empty()) return malformed(std::move(s.error));
  return report(b);
}

// wrp: time_stamp,x,y,z,pos_std,roll,pitch,yaw,status.
WaterLinkedParse sentence_dead_reckoning(std::span<const std::string_view> f) {
  if (f.size() != 9)
    return malformed("wrp has " + std::to_string(f.size()) + " fields, expected 9");
  SentenceFields s{f, {}};
  WaterLinkedDeadReckoning d;
  d.time_s = s.number(0, "time_stamp");
  d.position_m = {s.number(1, "x"), s.number(2, "y"), s.number(3, "z")};
  d.std_m = s.number(4, "pos_std");
  d.roll_deg = s.number(5, "roll");
  d.pitch_deg = s.number(6, "pitch");
  d.yaw_deg = s.number(7, "yaw");
  d.status = static_cast<int>(s.integer(8, "status").value_or(0));
  if (!s.error.empty()) return malformed(std::move(s.error));
  return report(d);
}

std::string join(std::span<const std::string_view> f) {
  std::string out;
  for (size_t i = 0; i < f.size(); ++i) {
    if (i) out += ',';
    out += f[i];
  }
  return out;
}

std::string hex2(uint8_t v) {
  char buf[3];
  std::snprintf(buf, sizeof buf, "%02x", v);
  return buf;
}

}  // namespace

uint8_t waterlinked_crc8(std::string_view bytes) {
  uint8_t crc = 0;
  for (const char ch : bytes) {
    crc ^= static_cast<uint8_t>(ch);
    for (int bit = 0; bit < 8; ++bit) {
      crc = static_cast<uint8_t>((crc & 0x80) ? (crc << 1) ^ 0x07 : crc << 1);
    }
  }
  return crc;
}

WaterLinkedParse parse_waterlinked_json(std::string_view line) {
  const json j = json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return malformed("not JSON");
  if (!j.is_object()) return malformed("not a JSON object");
  const auto type = j.find("type");
  if (type == j.end() || !type->is_string()) return malformed("no 'type'");
  const std::string& t = type->get_ref<const std::string&>();
  if (t == "velocity") return json_velocity(j, false);
  if (t == "velocity_water") return json_velocity(j, true);
  if (t == "position_local") return json_dead_reckoning(j);
  if (t == "response") return json_response(j);
  return {WaterLinkedLine::kUnknown, std::nullopt, {}};
}

WaterLinkedParse parse_waterlinked_sentence(std::string_view line) {
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.remove_suffix(1);
  if (line.size() < 3 || line[0] != 'w') return malformed("not a sentence (starts with 'w')");
  const size_t star = line.rfind('*');
  if (star == std::string_view::npos) return malformed("no checksum ('*xx')");
  const std::string_view body = line.substr(0, star), sum = line.substr(star + 1);
  unsigned expected = 0;
  const auto [end, ec] = std::from_chars(sum.data(), sum.data() + sum.size(), expected, 16);
  if (sum.size() != 2 || ec != std::errc() || end != sum.data() + sum.size()) {
    return malformed("checksum '" + std::string(sum) + "' is not two hex digits");
  }
  const uint8_t crc = waterlinked_crc8(body);
  if (crc != expected) {
    return {WaterLinkedLine::kBadChecksum, std::nullopt,
            "checksum " + std::string(sum) + ", computed " + hex2(crc)};
  }
  const std::vector<std::string_view> parts = split(body, ',');
  const std::string_view name = parts[0];
  const std::span<const std::string_view> f = std::span(parts).subspan(1);
  if (name == "wrz") return sentence_velocity(f, false);
  if (name == "wrs") return sentence_velocity(f, true);
  if (name == "wrx") return sentence_old_velocity(f);
  if (name == "wru") return sentence_beam(f);
  if (name == "wrp") return sentence_dead_reckoning(f);
  if (name == "wra" || name == "wrn" || name == "wr?" || name == "wr!" || name == "wrc" ||
      name == "wrv" || name == "wrw") {
    WaterLinkedResponse r;
    r.response_to = std::string(name);
    r.success = name != "wrn" && name != "wr?" && name != "wr!";
    r.result = join(f);
    return report(std::move(r));
  }
  return {WaterLinkedLine::kUnknown, std::nullopt, {}};
}

std::vector<WaterLinkedReport> WaterLinkedStream::feed(std::span<const uint8_t> bytes) {
  std::vector<WaterLinkedReport> out;
  for (const std::string& line : lines_.feed(bytes)) {
    WaterLinkedParse p = protocol_ == Protocol::kJson ? parse_waterlinked_json(line)
                                                      : parse_waterlinked_sentence(line);
    switch (p.kind) {
      case WaterLinkedLine::kUnknown:
        ++counters_.unknown;
        continue;
      case WaterLinkedLine::kMalformed:
        ++counters_.malformed;
        last_error_ = std::move(p.error);
        continue;
      case WaterLinkedLine::kBadChecksum:
        ++counters_.checksum_failures;
        last_error_ = std::move(p.error);
        continue;
      case WaterLinkedLine::kReport:
        break;
    }
    // Serial output protocol 1 sends every ping as both wrz and the deprecated wrx.
    if (const auto* v = std::get_if<WaterLinkedVelocity>(&*p.report)) {
      if (!v->deprecated_sentence && protocol_ == Protocol::kSerial) seen_wrz_ = true;
      if (v->deprecated_sentence && seen_wrz_) {
        ++counters_.superseded;
        continue;
      }
    }
    ++counters_.reports;
    out.push_back(std::move(*p.report));
  }
  return out;
}

std::string waterlinked_json_command(std::string_view command) {
  return json{{"command", command}}.dump() + "\n";
}

std::string waterlinked_json_set_config(const WaterLinkedConfig& c) {
  json p = json::object();
  if (c.speed_of_sound_mps) p["speed_of_sound"] = *c.speed_of_sound_mps;
  if (c.mounting_rotation_offset_deg)
    p["mounting_rotation_offset"] = *c.mounting_rotation_offset_deg;
  if (c.acoustic_enabled) p["acoustic_enabled"] = *c.acoustic_enabled;
  if (c.dark_mode_enabled) p["dark_mode_enabled"] = *c.dark_mode_enabled;
  if (c.range_mode) p["range_mode"] = *c.range_mode;
  if (c.periodic_cycling_enabled) p["periodic_cycling_enabled"] = *c.periodic_cycling_enabled;
  return json{{"command", "set_config"}, {"parameters", p}}.dump() + "\n";
}

std::string waterlinked_json_velocity(const WaterLinkedVelocity& v) {
  // JSON has no NaN: an unknown number is left out, or written as the DVL does (0, a beam without
  // return at -1).
  const auto number = [](double x, double none) { return std::isfinite(x) ? x : none; };
  json j = {{"vx", number(v.velocity_mps[0], 0)},
            {"vy", number(v.velocity_mps[1], 0)},
            {"vz", number(v.velocity_mps[2], 0)},
            {"velocity_valid", v.valid},
            {"status", v.status},
            {"format", v.format.empty() ? "json_v3.1" : v.format},
            {"type", v.water_track ? "velocity_water" : "velocity"}};
  for (const auto& [key, value] : {std::pair{"fom", v.fom_mps},
                                   {"altitude", v.altitude_m},
                                   {"time", v.since_last_report_ms}}) {
    if (std::isfinite(value)) j[key] = value;
  }
  if (std::all_of(v.covariance_m2ps2.begin(), v.covariance_m2ps2.end(),
                  [](double c) { return std::isfinite(c); })) {
    json rows = json::array();
    for (size_t r = 0; r < 3; ++r) {
      rows.push_back({v.covariance_m2ps2[3 * r], v.covariance_m2ps2[3 * r + 1],
                      v.covariance_m2ps2[3 * r + 2]});
    }
    j["covariance"] = rows;
  }
  json beams = json::array();
  for (const WaterLinkedBeam& b : v.beams) {
    beams.push_back({{"id", b.id},
                     {"velocity", number(b.velocity_mps, 0)},
                     {"distance", number(b.distance_m, -1)},
                     {"rssi", number(b.rssi_dbm, 0)},
                     {"nsd", number(b.nsd_dbm, 0)},
                     {"beam_valid", b.valid}});
  }
  j["transducers"] = beams;
  if (v.time_of_validity_us) j["time_of_validity"] = *v.time_of_validity_us;
  if (v.time_of_transmission_us) j["time_of_transmission"] = *v.time_of_transmission_us;
  return j.dump() + "\n";
}

std::optional<std::string> waterlinked_json_command_name(std::string_view line) {
  const json j = json::parse(line, nullptr, false);
  if (!j.is_object()) return std::nullopt;
  const auto c = j.find("command");
  if (c == j.end() || !c->is_string()) return std::nullopt;
  return c->get<std::string>();
}

std::string waterlinked_json_response(std::string_view command, bool success) {
  return json{{"response_to", command}, {"success", success},    {"error_message", ""},
              {"result", nullptr},      {"format", "json_v3.1"}, {"type", "response"}}
             .dump() +
         "\n";
}

std::string waterlinked_sentence(std::string_view body) {
  return std::string(body) + "*" + hex2(waterlinked_crc8(body)) + "\n";
}

std::string waterlinked_set_config_sentence(const WaterLinkedConfig& c) {
  const auto number = [](const std::optional<double>& v) {
    if (!v) return std::string();
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", *v);
    return std::string(buf);
  };
  const auto yes_no = [](const std::optional<bool>& v) {
    return v ? std::string(*v ? "y" : "n") : std::string();
  };
  return waterlinked_sentence("wcs," + number(c.speed_of_sound_mps) + "," +
                              number(c.mounting_rotation_offset_deg) + "," +
                              yes_no(c.acoustic_enabled) + "," + yes_no(c.dark_mode_enabled) + "," +
                              c.range_mode.value_or("") + "," + yes_no(c.periodic_cycling_enabled));
}

DvlSample to_dvl_sample(const WaterLinkedVelocity& report, const Eigen::Matrix3d& R_B_S,
                        int64_t timestamp_ns) {
  DvlSample s;
  s.timestamp_ns = timestamp_ns;
  if (report.time_of_validity_us) s.device_ns = *report.time_of_validity_us * 1000;
  const Eigen::Vector3d v_S(report.velocity_mps[0], report.velocity_mps[1], report.velocity_mps[2]);
  s.valid = report.valid && v_S.allFinite();
  s.velocity_B_mps = s.valid ? Eigen::Vector3d(R_B_S * v_S) : Eigen::Vector3d::Zero();
  for (const WaterLinkedBeam& b : report.beams) {
    if (b.valid && b.id >= 0 && b.id < kWaterLinkedBeams) {
      s.beam_range_m[static_cast<size_t>(b.id)] = b.distance_m;
    }
  }
  return s;
}

int64_t waterlinked_ping_host_ns(const WaterLinkedVelocity& report, int64_t arrival_ns,
                                 DeviceClock& clock) {
  if (!report.time_of_validity_us || !report.time_of_transmission_us) return arrival_ns;
  const int64_t sent_ns = *report.time_of_transmission_us * 1000;
  const int64_t ping_ns = *report.time_of_validity_us * 1000;
  // A report leaves ~0.2 s after its ping; one said to leave before it, or over 10 s after, has
  // times that disagree, and its arrival is the better stamp.
  if (sent_ns < ping_ns || sent_ns - ping_ns > 10'000'000'000) return arrival_ns;
  return clock.to_host_ns(sent_ns, arrival_ns) - (sent_ns - ping_ns);
}

}  // namespace pensight::drivers
