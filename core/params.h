#pragma once
// One definition per parameter: its key, unit, valid range and one-line help are written once, in
// a table beside the config struct they fill; the default is the struct's member initialiser.
// The YAML reader (read_params), the validity check of a config built in code (check_params), their
// error messages, and the documentation table (param_table, docs/parameters.md, `pensight params`)
// all read that table, so none of them can drift from another.
//
// A rule that ties two parameters together (max_range_m above min_range_m) stays a check of its
// own in the config's validate(), after check_params.
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include "core/error.h"
#include "core/strict_yaml.h"

namespace pensight {

// The valid values of a number: [min, max], either end open. NaN is never valid, an infinity only
// where `infinite` says so (a leg without end); an infinite end is printed as no bound.
struct ParamRange {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;
  bool max_open = false;
  bool infinite = false;

  bool contains(double v) const {
    return !std::isnan(v) && (infinite || std::isfinite(v)) && (min_open ? v > min : v >= min) &&
           (max_open ? v < max : v <= max);
  }
  // "> 0", ">= 0", "0.01 to 0.05", "(0, 0.5]", "any": what errors and docs print.
  std::string text() const;
};

inline constexpr ParamRange kAnyNumber{};
inline constexpr ParamRange kPositive{0, std::numeric_limits<double>::infinity(), true, false};
inline constexpr ParamRange kNonNegative{0, std::numeric_limits<double>::infinity()};
inline constexpr ParamRange kPositiveOrInfinite{0, std::numeric_limits<double>::infinity(), true,
                                                false, true};
constexpr ParamRange closed_range(double min, double max) {
  return {min, max};
}

// One parameter of Config: a member of type double, float, int, bool or optional double (absent:
// none).
template <class Config>
struct Param {
  std::string_view key;  // in the YAML map that holds Config's keys
  std::variant<double Config::*, float Config::*, int Config::*, bool Config::*,
               std::optional<double> Config::*>
      member;
  std::string_view unit;  // of the value as written ("m", "deg", "us"); empty for none
  ParamRange range;       // checked on the value as written; unused for bool
  std::string_view help;  // one line
  // The member holds the written value times this (a scene.yaml angle in degrees held in rad).
  double scale = 1;
  bool required = false;  // a file without the key is refused ("missing")
};

std::string format_param_value(double v);

// "VALUE is outside RANGE UNIT (HELP)": the one message of a value out of its range.
std::string param_range_error(double value, const ParamRange& range, std::string_view unit,
                              std::string_view help);

// Reads every parameter of `params` that `map` has into `config` (absent ones keep their value
// and, like every key asked about, count as known to check_unknown_keys), checking its range;
// throws pensight::Error "FILE: key 'PATH': VALUE is outside RANGE UNIT (HELP)". The caller reads
// the map's other keys and then calls map.check_unknown_keys().
template <class Config>
void read_params(const YamlMap& map, std::span<const Param<Config>> params, Config& config) {
  for (const Param<Config>& p : params) {
    const std::string key(p.key);
    if (!map.has(key)) {
      if (p.required) map.fail(key, "missing; add it (" + std::string(p.help) + ")");
      continue;
    }
    if (const auto* flag = std::get_if<bool Config::*>(&p.member)) {
      config.*(*flag) = map.boolean(key);
      continue;
    }
    const double v = std::holds_alternative<int Config::*>(p.member)
                         ? static_cast<double>(map.integer(key))
                         : map.number(key);
    if (!p.range.contains(v)) map.fail(key, param_range_error(v, p.range, p.unit, p.help));
    if (const auto* number = std::get_if<double Config::*>(&p.member)) {
      config.*(*number) = v * p.scale;
    } else if (const auto* single = std::get_if<float Config::*>(&p.member)) {
      config.*(*single) = static_cast<float>(v * p.scale);
    } else if (const auto* maybe = std::get_if<std::optional<double> Config::*>(&p.member)) {
      config.*(*maybe) = v * p.scale;
    } else {
      config.*std::get<int Config::*>(p.member) = static_cast<int>(v);
    }
  }
}

template <class Config, size_t N>
void read_params(const YamlMap& map, const Param<Config> (&params)[N], Config& config) {
  read_params(map, std::span<const Param<Config>>(params), config);
}

// The value of p in `config`, as written (divided by p.scale); bools as 0 / 1, an absent optional
// as NaN.
template <class Config>
double param_value(const Config& config, const Param<Config>& p) {
  if (const auto* flag = std::get_if<bool Config::*>(&p.member)) return config.*(*flag) ? 1 : 0;
  if (const auto* integer = std::get_if<int Config::*>(&p.member)) return config.*(*integer);
  if (const auto* single = std::get_if<float Config::*>(&p.member)) {
    return config.*(*single) / p.scale;
  }
  if (const auto* maybe = std::get_if<std::optional<double> Config::*>(&p.member)) {
    const std::optional<double>& v = config.*(*maybe);
    return v ? *v / p.scale : std::numeric_limits<double>::quiet_NaN();
  }
  return config.*std::get<double Config::*>(p.member) / p.scale;
}

// Checks a config built in code against the ranges; throws pensight::Error
// "WHERE: key 'PREFIXKEY': VALUE is outside RANGE UNIT (HELP)" for the first value out of range.
template <class Config>
void check_params(const Config& config, std::span<const Param<Config>> params,
                  std::string_view where, std::string_view key_prefix = "") {
  for (const Param<Config>& p : params) {
    if (std::holds_alternative<bool Config::*>(p.member)) continue;
    const double v = param_value(config, p);
    const auto* maybe = std::get_if<std::optional<double> Config::*>(&p.member);
    if (maybe && !(config.*(*maybe))) continue;
    if (!p.range.contains(v)) {
      throw Error(std::string(where) + ": key '" + std::string(key_prefix) + std::string(p.key) +
                  "': " + param_range_error(v, p.range, p.unit, p.help));
    }
  }
}

// Markdown rows "| key | default | unit | valid | help |" for `params`, each key after
// `key_prefix` ("limits."), the defaults those of `defaults`.
template <class Config>
std::string param_table_rows(std::span<const Param<Config>> params, const Config& defaults = {},
                             std::string_view key_prefix = "") {
  std::string rows;
  for (const Param<Config>& p : params) {
    const bool flag = std::holds_alternative<bool Config::*>(p.member);
    const double v = param_value(defaults, p);
    rows += "| `" + std::string(key_prefix) + std::string(p.key) + "` | " +
            (p.required ? "required"
             : flag     ? (v != 0 ? "true" : "false")
                        : format_param_value(v)) +
            " | " + std::string(p.unit) + " | " + (flag ? "true, false" : p.range.text()) + " | " +
            std::string(p.help) + " |\n";
  }
  return rows;
}

// The header of the table param_table_rows fills.
inline constexpr std::string_view kParamTableHeader =
    "| key | default | unit | valid | meaning |\n|---|---|---|---|---|\n";

}  // namespace pensight
