#pragma once
// Checked reading of YAML mappings (sensor.yaml, scene.yaml, scenarios): a missing key and a value
// of the wrong type are errors that name the file and the full key path. A key nobody asks for is
// an error in the project's own files (UnknownKeys::kReject: a typo never silently falls back to
// a default) and one note per file in dataset files, which other tools write with keys of their
// own (UnknownKeys::kNote, ../shared/dataset-format.md).
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace pensight {

enum class UnknownKeys { kReject, kNote };

class YamlMap {
 public:
  // Parses `file`; throws pensight::Error when it is missing, not YAML or not a mapping.
  static YamlMap load_file(const std::filesystem::path& file,
                           UnknownKeys unknown = UnknownKeys::kReject);
  // Parses YAML text; `file` only names the source in messages.
  static YamlMap parse(const std::string& text, const std::string& file,
                       UnknownKeys unknown = UnknownKeys::kReject);

  const std::string& file() const { return file_; }
  // "key" at the top level, "parent.key" below.
  std::string key_path(const std::string& key) const;
  // Every key asked about, present or not, is a known key in check_unknown_keys' message.
  bool has(const std::string& key) const;
  // The kind of a present value, for keys that come in more than one form.
  bool is_list(const std::string& key) const;
  bool is_map(const std::string& key) const;

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
  // A list of `rows` lists of `cols` numbers ([[1, 2], [3, 4]]); any other shape fails with
  // `shape`, which says what the value should look like.
  std::vector<std::vector<double>> number_rows(const std::string& key, size_t rows, size_t cols,
                                               const std::string& shape) const;
  YamlMap map(const std::string& key) const;
  std::optional<YamlMap> optional_map(const std::string& key) const;
  std::vector<YamlMap> map_list(const std::string& key) const;
  // nullopt when the key is absent.
  std::optional<std::vector<YamlMap>> optional_map_list(const std::string& key) const;

  // Deals with the keys of this mapping that no accessor above has asked for. kReject: throws
  // naming the first (a typo). kNote: collects their paths; on the top-level map it logs them all
  // in one note per file. Call it once all keys of this level have been read, on nested maps
  // (which check their own keys) before their parent.
  void check_unknown_keys() const;
  // Throws "FILE: key 'PATH': MESSAGE".
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

 private:
  // What the maps of one file share: how unknown keys are dealt with, and those found so far.
  struct FileState {
    UnknownKeys unknown;
    std::vector<std::string> unknown_found;
  };

  YamlMap(YAML::Node node, std::string file, std::string prefix, std::shared_ptr<FileState> state);
  YAML::Node required(const std::string& key) const;
  double to_number(const YAML::Node& n, const std::string& key) const;

  YAML::Node node_;
  std::string file_;
  std::string prefix_;
  std::shared_ptr<FileState> state_;
  std::shared_ptr<std::set<std::string>> used_ = std::make_shared<std::set<std::string>>();
};

}  // namespace pensight
