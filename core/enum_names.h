#pragma once
// One table per enum gives its names both ways: to_string, the parser and the list of choices an
// error message offers all read it, so a new value is named in one place.
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace pensight {

template <class Enum>
struct EnumName {
  Enum value;
  const char* name;
};

// The name of `value`; "unknown" for a value the table lacks.
template <class Enum>
const char* enum_name(std::span<const EnumName<Enum>> names, Enum value) {
  for (const EnumName<Enum>& n : names) {
    if (n.value == value) return n.name;
  }
  return "unknown";
}

// The value named `name`; nullopt for any other name.
template <class Enum>
std::optional<Enum> parse_enum_name(std::span<const EnumName<Enum>> names, std::string_view name) {
  for (const EnumName<Enum>& n : names) {
    if (name == n.name) return n.value;
  }
  return std::nullopt;
}

// "a, b or c": the choices an error message lists.
template <class Enum>
std::string enum_choices(std::span<const EnumName<Enum>> names) {
  std::string text;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0) text.append(i + 1 == names.size() ? " or " : ", ");
    text.append(names[i].name);
  }
  return text;
}

}  // namespace pensight
