#include "core/strict_yaml.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/log.h"

namespace pensight {

YamlMap::YamlMap(YAML::Node node, std::string file, std::string prefix,
                 std::shared_ptr<FileState> state)
    : node_(std::move(node)),
      file_(std::move(file)),
      prefix_(std::move(prefix)),
      state_(std::move(state)) {}

YamlMap YamlMap::load_file(const std::filesystem::path& file, UnknownKeys unknown) {
  std::ifstream in(file);
  if (!in) throw Error("cannot open '" + file.string() + "': check that the file exists");
  std::stringstream text;
  text << in.rdbuf();
  return parse(text.str(), file.string(), unknown);
}

YamlMap YamlMap::parse(const std::string& text, const std::string& file, UnknownKeys unknown) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw Error(file + ": not valid YAML (line " + std::to_string(e.mark.line + 1) + "): " + e.msg);
  }
  if (!root.IsMap()) throw Error(file + ": expected a YAML mapping of 'key: value' lines");
  return YamlMap(root, file, "", std::make_shared<FileState>(FileState{unknown, {}}));
}

std::string YamlMap::key_path(const std::string& key) const {
  return prefix_.empty() ? key : prefix_ + "." + key;
}

bool YamlMap::has(const std::string& key) const {
  used_->insert(key);
  return node_[key].IsDefined() && !node_[key].IsNull();
}

bool YamlMap::is_list(const std::string& key) const {
  return has(key) && node_[key].IsSequence();
}

bool YamlMap::is_map(const std::string& key) const {
  return has(key) && node_[key].IsMap();
}

void YamlMap::fail(const std::string& key, const std::string& message) const {
  throw Error(file_ + ": key '" + key_path(key) + "': " + message);
}

YAML::Node YamlMap::required(const std::string& key) const {
  if (!has(key)) fail(key, "missing; add it to the file");
  return node_[key];
}

double YamlMap::to_number(const YAML::Node& n, const std::string& key) const {
  if (!n.IsScalar()) fail(key, "expected a number");
  double v = 0;
  if (!YAML::convert<double>::decode(n, v) || !std::isfinite(v)) {
    fail(key, "expected a finite number, got '" + n.Scalar() + "'");
  }
  return v;
}

double YamlMap::number(const std::string& key) const {
  return to_number(required(key), key);
}

double YamlMap::number(const std::string& key, double fallback) const {
  return optional_number(key).value_or(fallback);
}

std::optional<double> YamlMap::optional_number(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return to_number(node_[key], key);
}

int YamlMap::integer(const std::string& key) const {
  const double v = number(key);
  if (v != std::round(v) || std::abs(v) > 2e9) fail(key, "expected an integer");
  return static_cast<int>(v);
}

int YamlMap::integer(const std::string& key, int fallback) const {
  return has(key) ? integer(key) : fallback;
}

int64_t YamlMap::integer64(const std::string& key, int64_t fallback) const {
  if (!has(key)) return fallback;
  const YAML::Node n = required(key);
  long long v = 0;
  if (!n.IsScalar() || !YAML::convert<long long>::decode(n, v)) {
    fail(key, "expected a whole number, got '" + (n.IsScalar() ? n.Scalar() : std::string()) + "'");
  }
  return static_cast<int64_t>(v);
}

bool YamlMap::boolean(const std::string& key) const {
  const YAML::Node n = required(key);
  bool v = false;
  if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) {
    fail(key, "expected true or false");
  }
  return v;
}

bool YamlMap::boolean(const std::string& key, bool fallback) const {
  return has(key) ? boolean(key) : fallback;
}

std::string YamlMap::string(const std::string& key) const {
  const YAML::Node n = required(key);
  if (!n.IsScalar()) fail(key, "expected a text value");
  return n.Scalar();
}

std::string YamlMap::string(const std::string& key, const std::string& fallback) const {
  return has(key) ? string(key) : fallback;
}

std::vector<double> YamlMap::numbers(const std::string& key, size_t size) const {
  const YAML::Node n = required(key);
  if (!n.IsSequence()) fail(key, "expected a list of numbers like [1.0, 2.0]");
  if (size != 0 && n.size() != size) {
    fail(key, "expected " + std::to_string(size) + " numbers, got " + std::to_string(n.size()));
  }
  std::vector<double> out;
  for (const auto& e : n) out.push_back(to_number(e, key));
  return out;
}

std::vector<std::vector<double>> YamlMap::number_rows(const std::string& key, size_t rows,
                                                      size_t cols, const std::string& shape) const {
  const YAML::Node n = required(key);
  if (!n.IsSequence() || n.size() != rows) fail(key, shape);
  std::vector<std::vector<double>> out;
  for (const auto& row : n) {
    if (!row.IsSequence() || row.size() != cols) fail(key, shape);
    std::vector<double>& r = out.emplace_back();
    for (const auto& e : row) r.push_back(to_number(e, key));
  }
  return out;
}

YamlMap YamlMap::map(const std::string& key) const {
  const YAML::Node n = required(key);
  if (!n.IsMap()) fail(key, "expected a mapping of 'key: value' entries");
  return YamlMap(n, file_, key_path(key), state_);
}

std::optional<YamlMap> YamlMap::optional_map(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return map(key);
}

std::vector<YamlMap> YamlMap::map_list(const std::string& key) const {
  const YAML::Node n = required(key);
  if (!n.IsSequence()) fail(key, "expected a list of mappings ('- key: value' entries)");
  std::vector<YamlMap> out;
  for (size_t i = 0; i < n.size(); ++i) {
    const std::string item = key + "[" + std::to_string(i) + "]";
    if (!n[i].IsMap()) fail(item, "expected a mapping of 'key: value' entries");
    out.push_back(YamlMap(n[i], file_, key_path(item), state_));
  }
  return out;
}

std::optional<std::vector<YamlMap>> YamlMap::optional_map_list(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return map_list(key);
}

void YamlMap::check_unknown_keys() const {
  for (const auto& kv : node_) {
    if (!kv.first.IsScalar()) {
      throw Error(file_ + ": " + (prefix_.empty() ? "top level" : "key '" + prefix_ + "'") +
                  ": a key that is a list or a mapping; keys are plain names");
    }
    const std::string key = kv.first.Scalar();
    if (used_->count(key) != 0) continue;
    if (state_->unknown == UnknownKeys::kNote) {
      state_->unknown_found.push_back(key_path(key));
      continue;
    }
    std::string known;
    for (const auto& k : *used_) known += (known.empty() ? "" : ", ") + k;
    fail(key, "unknown key (a typo?); known keys here: " + known);
  }
  if (prefix_.empty() && !state_->unknown_found.empty()) {
    std::string keys;
    for (const auto& k : state_->unknown_found) keys += (keys.empty() ? "" : ", ") + k;
    log_info(file_ + ": keys not used by pensight: " + keys);
  }
}

}  // namespace pensight
