#include "pipeline/dataset/trajectory_tum.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/error.h"
#include "core/units.h"

namespace pensight {
namespace {

constexpr int64_t kNsPerS = 1'000'000'000;

// Seconds with nine decimals from the integer nanoseconds: a double holds ~16 digits, too few
// for nanoseconds of an epoch timestamp (1.7e9 s).
std::string seconds_text(int64_t t_ns) {
  const uint64_t magnitude =
      t_ns < 0 ? static_cast<uint64_t>(-(t_ns + 1)) + 1 : static_cast<uint64_t>(t_ns);
  char buf[40];
  std::snprintf(buf, sizeof buf, "%s%" PRIu64 ".%09" PRIu64, t_ns < 0 ? "-" : "",
                magnitude / kNsPerS, magnitude % kNsPerS);
  return buf;
}

// The exact nanoseconds of a fixed-point seconds field ("1700000000.123456789"); other forms
// (an exponent) through a double.
bool parse_seconds(const std::string& s, int64_t& t_ns) {
  size_t i = 0;
  const bool negative = !s.empty() && s[0] == '-';
  if (negative || (!s.empty() && s[0] == '+')) ++i;
  int64_t whole = 0, frac = 0;
  int whole_digits = 0, frac_digits = 0;
  for (; i < s.size() && std::isdigit(static_cast<unsigned char>(s[i])); ++i, ++whole_digits) {
    if (whole_digits >= 10) return false;
    whole = whole * 10 + (s[i] - '0');
  }
  if (i < s.size() && s[i] == '.') {
    for (++i; i < s.size() && std::isdigit(static_cast<unsigned char>(s[i])); ++i, ++frac_digits)
      if (frac_digits < 9) frac = frac * 10 + (s[i] - '0');
  }
  // 9e9 s keeps the nanoseconds within int64.
  if (i == s.size() && whole_digits + frac_digits > 0 && whole <= 9'000'000'000) {
    for (int d = std::min(frac_digits, 9); d < 9; ++d) frac *= 10;
    t_ns = (negative ? -1 : 1) * (whole * kNsPerS + frac);
    return true;
  }
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(v) ||
      std::abs(v) > 9e9)
    return false;
  t_ns = seconds_to_ns(v);
  return true;
}

}  // namespace

std::string tum_line(int64_t timestamp_ns, const Eigen::Isometry3d& T_pen_body) {
  Eigen::Quaterniond q(T_pen_body.linear());
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const Eigen::Vector3d p = T_pen_body.translation();
  std::ostringstream line;
  line << seconds_text(timestamp_ns);
  for (const double v : {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()})
    line << ' ' << format_number(v);
  line << '\n';
  return line.str();
}

TrajectoryTumWriter::TrajectoryTumWriter(const std::filesystem::path& file)
    : file_(std::make_unique<AtomicFile>(file)) {}

TrajectoryTumWriter::~TrajectoryTumWriter() = default;

bool TrajectoryTumWriter::write(int64_t timestamp_ns, const Eigen::Isometry3d& T_pen_body) {
  if (!file_) throw Error("TrajectoryTumWriter::write after finish");
  if (!T_pen_body.matrix().allFinite()) return false;
  file_->stream() << tum_line(timestamp_ns, T_pen_body);
  return true;
}

void TrajectoryTumWriter::finish() {
  if (!file_) throw Error("TrajectoryTumWriter::finish called twice");
  file_->commit();
  file_.reset();
}

std::vector<TumPose> read_trajectory_tum(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw Error("cannot open '" + file.string() + "': check that the file exists");
  std::vector<TumPose> poses;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream fields(line);
    std::vector<std::string> f;
    for (std::string w; fields >> w;) f.push_back(w);
    if (f.empty() || f[0][0] == '#') continue;
    const auto fail = [&](const std::string& why) {
      throw Error(file.string() + ":" + std::to_string(number) + ": " + why +
                  " (TUM trajectory: \"t x y z qx qy qz qw\")");
    };
    if (f.size() != 8) fail("expected 8 space-separated numbers, got " + std::to_string(f.size()));
    TumPose p;
    if (!parse_seconds(f[0], p.timestamp_ns))
      fail("expected a time in seconds, got '" + f[0] + "'");
    double v[7];
    for (size_t k = 0; k < 7; ++k) {
      char* end = nullptr;
      errno = 0;
      v[k] = std::strtod(f[k + 1].c_str(), &end);
      if (end != f[k + 1].c_str() + f[k + 1].size() || errno == ERANGE || !std::isfinite(v[k]))
        fail("field " + std::to_string(k + 2) + ": expected a number, got '" + f[k + 1] + "'");
    }
    p.p_m = {v[0], v[1], v[2]};
    p.q = Eigen::Quaterniond(v[6], v[3], v[4], v[5]);  // w, x, y, z
    poses.push_back(p);
  }
  return poses;
}

}  // namespace pensight
