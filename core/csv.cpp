#include "core/csv.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>

#include "core/error.h"

namespace pensight {
namespace {

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const size_t e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

}  // namespace

CsvTable::CsvTable(const std::filesystem::path& file, size_t min_fields, size_t max_fields,
                   BadRows bad_rows)
    : file_(file.string()) {
  std::ifstream in(file);
  if (!in) throw Error("cannot open '" + file_ + "': check that the file exists");
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string t = trim(line);
    if (t.empty()) continue;
    if (t[0] == '#') {
      if (header_.empty()) header_ = split(t.substr(1));
      continue;
    }
    Row row{number, split(t)};
    if (row.fields.size() < min_fields || row.fields.size() > max_fields) {
      const std::string message =
          file_ + ":" + std::to_string(number) + ": expected " +
          (min_fields == max_fields ? std::to_string(min_fields)
           : max_fields == std::numeric_limits<size_t>::max()
               ? "at least " + std::to_string(min_fields)
               : std::to_string(min_fields) + " to " + std::to_string(max_fields)) +
          " comma-separated fields, got " + std::to_string(row.fields.size());
      if (bad_rows == BadRows::kThrow) throw Error(message);
      rejected_.push_back({number, message});
      continue;
    }
    rows_.push_back(std::move(row));
  }
}

void CsvTable::fail(size_t row, size_t field, const std::string& message) const {
  throw Error(file_ + ":" + std::to_string(rows_[row].line) + ": field " +
              std::to_string(field + 1) + ": " + message);
}

double CsvTable::number(size_t row, size_t field) const {
  const std::string& s = text(row, field);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE || std::isinf(v)) {
    fail(row, field, "expected a number (or nan), got '" + s + "'");
  }
  return v;
}

int64_t CsvTable::integer(size_t row, size_t field) const {
  const std::string& s = text(row, field);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE) {
    fail(row, field, "expected an integer (timestamps are integer nanoseconds), got '" + s + "'");
  }
  return static_cast<int64_t>(v);
}

std::string format_number(double v) {
  if (std::isnan(v)) return "nan";
  if (v == 0) return "0";  // not "-0"
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace pensight
