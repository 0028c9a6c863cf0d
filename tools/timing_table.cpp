#include "tools/timing_table.h"

#include <cstdio>
#include <sstream>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/dataset_types.h"

namespace pensight {
namespace {

struct Published {
  const char* node;
  double mean_ms;
  double rate_hz;
};
// Tab. 3 of the published pipeline (Jetson Orin, ROS 1; its dense depth is TRUDepth); rates only
// where it gives them.
constexpr Published kPublished[] = {
    {"fft net detection", 47.8, kNaN},   {"dense depth", 66.8, kNaN},
    {"relative pose (fft)", 13.2, kNaN}, {"relative pose (depth)", 44.6, kNaN},
    {"global pose", 8.7, 4.0},           {"map", kNaN, 0.5},
};

StageStats not_run(const char* name) {
  StageStats s;
  s.name = name;
  s.mean_ms = s.p95_ms = s.max_ms = s.rate_hz = s.latency_mean_ms = s.latency_p95_ms = kNaN;
  return s;
}

}  // namespace

std::vector<TimingRow> timing_table(std::span<const StageStats> stages) {
  std::vector<TimingRow> rows;
  for (const Published& p : kPublished) {
    TimingRow row{not_run(p.node), p.mean_ms, p.rate_hz};
    for (const StageStats& s : stages) {
      if (s.name == p.node) row.ours = s;
    }
    rows.push_back(row);
  }
  for (const StageStats& s : stages) {
    bool published = false;
    for (const Published& p : kPublished) published = published || s.name == p.node;
    if (!published) rows.push_back({s, kNaN, kNaN});
  }
  for (const StageStats& s : stages) {
    if (s.name != "global pose") continue;
    StageStats e2e = s;
    e2e.name = "end-to-end (camera -> global pose)";
    e2e.mean_ms = s.latency_mean_ms;
    e2e.p95_ms = s.latency_p95_ms;
    e2e.max_ms = kNaN;
    rows.push_back({e2e, kNaN, kNaN});
  }
  return rows;
}

std::string format_timing_table(std::span<const TimingRow> rows) {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof(line), "  %-36s %7s %9s %9s %8s %11s | %12s %9s\n", "node", "count",
                "mean ms", "p95 ms", "rate Hz", "latency ms", "Orin mean ms", "Orin Hz");
  out << line;
  for (const TimingRow& r : rows) {
    const StageStats& s = r.ours;
    if (s.processed == 0) {
      std::snprintf(line, sizeof(line), "  %-36s %7s %9s %9s %8s %11s | %12s %9s\n", s.name.c_str(),
                    "-", "not run", "", "", "", format_number(r.published_ms).c_str(),
                    format_number(r.published_rate_hz).c_str());
    } else {
      std::snprintf(line, sizeof(line), "  %-36s %7zu %9.2f %9.2f %8.1f %11.2f | %12s %9s\n",
                    s.name.c_str(), s.processed, s.mean_ms, s.p95_ms, s.rate_hz, s.latency_mean_ms,
                    format_number(r.published_ms).c_str(),
                    format_number(r.published_rate_hz).c_str());
    }
    out << line;
  }
  return out.str();
}

void write_timing_csv(const std::filesystem::path& file, std::span<const TimingRow> rows) {
  AtomicFile f(file);
  std::ostream& out = f.stream();
  out << "#node,count,mean_ms,p95_ms,max_ms,rate_hz,latency_mean_ms,latency_p95_ms,"
         "published_mean_ms,published_rate_hz\n";
  for (const TimingRow& r : rows) {
    const StageStats& s = r.ours;
    out << s.name << "," << s.processed;
    for (double v : {s.mean_ms, s.p95_ms, s.max_ms, s.rate_hz, s.latency_mean_ms, s.latency_p95_ms,
                     r.published_ms, r.published_rate_hz}) {
      out << "," << format_number(v);
    }
    out << "\n";
  }
  f.commit();
}

}  // namespace pensight
