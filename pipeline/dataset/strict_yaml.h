#pragma once
// Strict reading of YAML mappings for configuration files (sensor.yaml, scene.yaml, scenarios):
// a missing key, a value of the wrong type and a key nobody asked for are all errors that name
// the file and the full key path, so a typo never silently falls back to a default.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace pensight {

class YamlMap {
 public:
  // Parses `file`; throws pensight::Error when it is missing, not YAML or not a mapping.
  static YamlMap load_file(const std::filesystem::path& file);
  // Parses YAML text; `file` only names the source in messages.
  static YamlMap parse(const std::string& text, const std::string& file);

  const std::string& file() const { return file_; }
  // "key" at the top level, "parent.key" below.
  std::string key_path(const std::string& key) const;
  bool has(const std::string& key) const;

  double number(const std::string& key) const;
  double number(const std::string& key, double fallback) const;
  std::optional<double> optional_number(const std::string& key) const;
  int integer(const std::string& key) const;
  int integer(const std::string& key, int fallback) const;
  // Whole 64-bit integers (e.g. nanosecond timestamps), read without going through double.
  int64_t integer64(const std::string& key, int64_t fallback) const;
  bool boolean(const std::string& key) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::string string(const std::string& key) const;
  std::string string(const std::string& key, const std::string& fallback) const;
  // A sequence of numbers; `size` (when not 0) is the required length.
  std::vector<double> numbers(const std::string& key, size_t size = 0) const;
  YamlMap map(const std::string& key) const;
  std::optional<YamlMap> optional_map(const std::string& key) const;
  std::vector<YamlMap> map_list(const std::string& key) const;
  // nullopt when the key is absent (it still counts as known in reject_unknown_keys' message).
  std::optional<std::vector<YamlMap>> optional_map_list(const std::string& key) const;

  // Throws naming the first key of this mapping that no accessor above has asked for (typos).
  // Call it once all keys of this level have been read; nested maps check their own keys.
  void reject_unknown_keys() const;
  // Throws "FILE: key 'PATH': MESSAGE".
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

 private:
  YamlMap(YAML::Node node, std::string file, std::string prefix);
  YAML::Node required(const std::string& key) const;
  double to_number(const YAML::Node& n, const std::string& key) const;

  YAML::Node node_;
  std::string file_;
  std::string prefix_;
  std::shared_ptr<std::set<std::string>> used_ = std::make_shared<std::set<std::string>>();
};

}  // namespace pensight
