#include "core/params.h"

#include <cstdio>

namespace pensight {

std::string format_param_value(double v) {
  if (std::isnan(v)) return "none";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

std::string param_range_error(double value, const ParamRange& range, std::string_view unit,
                              std::string_view help) {
  std::string message = format_param_value(value);
  message.append(" is outside ").append(range.text());
  if (!unit.empty()) message.append(" ").append(unit);
  return message.append(" (").append(help).append(")");
}

std::string ParamRange::text() const {
  // Built by appending: GCC 12 warns falsely (-Wrestrict, PR 105329) on "literal" + std::string.
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  std::string t;
  if (!has_min && !has_max) {
    t = "any";
  } else if (!has_max) {
    t.append(min_open ? "> " : ">= ").append(format_param_value(min));
  } else if (!has_min) {
    t.append(max_open ? "< " : "<= ").append(format_param_value(max));
  } else if (!min_open && !max_open) {
    t.append(format_param_value(min)).append(" to ").append(format_param_value(max));
  } else {
    t.append(min_open ? "(" : "[").append(format_param_value(min)).append(", ");
    t.append(format_param_value(max)).append(max_open ? ")" : "]");
  }
  return t;
}

}  // namespace pensight
