#include "tools/report/report_html.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_bytes.h"
#include "core/units.h"
#include "pipeline/dataset/diagnostics_csv.h"
#include "pipeline/dataset/estimates_csv.h"
#include "pipeline/dataset/global_pose_csv.h"
#include "tools/evaluation/evaluation.h"
#include "tools/report/svg_chart.h"
#include "tools/timing_table.h"

namespace pensight {
namespace {

std::string base64(std::string_view bytes) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    uint32_t v = 0;
    for (size_t k = 0; k < 3; ++k) {
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    }
    for (size_t k = 0; k < 4; ++k) {
      out += k <= n ? kDigits[(v >> (18 - 6 * k)) & 63] : '=';
    }
  }
  return out;
}

// Table cells: integers as such, otherwise about three significant digits.
std::string short_number(double v) {
  if (!std::isfinite(v)) return "n/a";
  if (v == std::round(v) && std::abs(v) < 1e9) return printf_double("%.0f", v);
  if (std::abs(v) >= 100) return printf_double("%.0f", v);
  return printf_double("%.3g", v);
}

// Angles as a continuous curve (no jumps of 2 pi where an angle crosses +-pi).
void unwrap(std::vector<double>& angles_rad) {
  double last = kNaN, turns = 0;
  for (double& a : angles_rad) {
    if (!std::isfinite(a)) continue;
    if (std::isfinite(last)) {
      turns += 2 * std::numbers::pi * std::round((last - (a + turns)) / (2 * std::numbers::pi));
    }
    a += turns;
    last = a;
  }
}

std::string not_available(const std::string& why) {
  return "<p class=\"absent\">" + html_escape(why) + ".</p>\n";
}

// The page names an absent part of the run by the file it would have been written to.
std::string not_written(const char* file) {
  return std::string(file) + " was not written by this run";
}

// ---- The page ----------------------------------------------------------------------------------

constexpr const char* kEstimateColour = "#1f5fbf";
constexpr const char* kTruthColour = "#222";
constexpr const char* kDvlColour = "#d2691e";
constexpr const char* kPublishedColour = "#b03060";

struct Run {
  const ReportInput& in;
  std::span<const EstimateRow> rows;       // *in.estimates
  std::span<const EstimateRow> published;  // empty when in.published is absent
  int64_t t0_ns = 0;                       // the first frame's: time 0 of the plots
  const GroundTruth* truth = nullptr;

  double seconds(int64_t t_ns) const { return seconds_between(t0_ns, t_ns); }
  std::vector<double> times(std::span<const EstimateRow> r) const {
    std::vector<double> t;
    for (const EstimateRow& e : r) t.push_back(seconds(e.timestamp_ns));
    return t;
  }
  // Truth rows inside the run's time span.
  std::vector<const GroundTruthRow*> truth_rows() const {
    std::vector<const GroundTruthRow*> out;
    if (!truth || rows.empty()) return out;
    for (const GroundTruthRow& g : truth->rows) {
      if (g.timestamp_ns >= rows.front().timestamp_ns && g.timestamp_ns <= rows.back().timestamp_ns)
        out.push_back(&g);
    }
    return out;
  }
};

template <class Row, class F>
std::vector<double> column(std::span<const Row> rows, F f) {
  std::vector<double> v;
  for (const Row& r : rows) v.push_back(f(r));
  return v;
}

std::string net_pose_section(const Run& run) {
  std::string html = "<h2>Net-relative pose (FFT)</h2>\n";
  const std::vector<double> t = run.times(run.rows);
  const auto truth = run.truth_rows();
  std::vector<double> t_truth;
  for (const GroundTruthRow* g : truth) t_truth.push_back(run.seconds(g->timestamp_ns));
  std::vector<double> t_dvl, dvl_d, dvl_psi;
  const bool dvl = run.in.diagnostics.has_value();
  if (dvl) {
    for (const DiagnosticsRow& d : *run.in.diagnostics) {
      t_dvl.push_back(run.seconds(d.timestamp_ns));
      dvl_d.push_back(d.dvl_plane_d_m);
      dvl_psi.push_back(rad_to_deg(d.dvl_plane_psi_rad));
    }
  }
  struct Quantity {
    const char* title;
    const char* unit;
    double EstimateRow::*estimate;
    double GroundTruthRow::*truth;
    bool angle;
    const std::vector<double>* dvl;
  };
  const Quantity quantities[] = {
      {"d_net: distance to the net along the optical axis", "m", &EstimateRow::d_net_fft_m,
       &GroundTruthRow::d_net_m, false, &dvl_d},
      {"psi_net: heading against the net", "deg", &EstimateRow::psi_net_fft_rad,
       &GroundTruthRow::psi_net_rad, true, &dvl_psi},
      {"pitch_net: pitch against the net", "deg", &EstimateRow::pitch_net_fft_rad,
       &GroundTruthRow::pitch_net_rad, true, nullptr}};
  for (const Quantity& q : quantities) {
    Chart c;
    c.title = q.title;
    c.x_label = "time [s]";
    c.y_label = std::string(q.unit);
    c.series.push_back({"estimate (estimates.csv)", kEstimateColour, t,
                        column<EstimateRow>(run.rows, [&](const EstimateRow& r) {
                          return q.angle ? rad_to_deg(r.*q.estimate) : r.*q.estimate;
                        })});
    if (dvl && q.dvl) c.series.push_back({"DVL net plane", kDvlColour, t_dvl, *q.dvl, true});
    if (!truth.empty()) {
      std::vector<double> y;
      for (const GroundTruthRow* g : truth) {
        y.push_back(q.angle ? rad_to_deg(g->*q.truth) : g->*q.truth);
      }
      c.series.push_back({"truth", kTruthColour, t_truth, y, true});
    }
    html += svg(c);
  }
  std::string notes;
  if (!dvl) notes += "DVL net plane: " + not_written(kDiagnosticsFile);
  if (truth.empty()) {
    if (!notes.empty()) notes += "; ";
    notes += run.in.dataset ? "the dataset has no groundtruth0 for these frames"
                            : "no dataset given: no ground truth";
  }
  if (!notes.empty()) html += not_available(notes);
  return html;
}

std::string global_pose_section(const Run& run) {
  std::string html = "<h2>Global pose in the pen</h2>\n";
  const auto truth = run.truth_rows();
  std::vector<double> t_truth, truth_x, truth_y, truth_r, truth_rho, truth_z, truth_psi;
  for (const GroundTruthRow* g : truth) {
    t_truth.push_back(run.seconds(g->timestamp_ns));
    const Eigen::Vector3d& p = g->p_pen_body_m;
    truth_r.push_back(std::hypot(p.x(), p.y()));
    truth_rho.push_back(std::atan2(p.y(), p.x()));
    truth_z.push_back(p.z());
    truth_psi.push_back(g->yaw_rad);
  }
  // The pen's azimuth origin is not observable (dataset-format.md): as `pensight evaluate`
  // compares changes, the truth's rho and yaw are shifted to agree with the estimate at the first
  // frame with rho_g, psi_g and a truth row, and the truth's track is turned by the same rho.
  double rho_offset = 0, psi_offset = 0;
  bool aligned = false;
  for (const EstimateRow& r : run.rows) {
    if (!std::isfinite(r.rho_g_rad) || !std::isfinite(r.psi_g_rad)) continue;
    const auto it = std::find_if(truth.begin(), truth.end(), [&](const GroundTruthRow* g) {
      return g->timestamp_ns == r.timestamp_ns;
    });
    if (it == truth.end()) continue;
    rho_offset = r.rho_g_rad - std::atan2((*it)->p_pen_body_m.y(), (*it)->p_pen_body_m.x());
    psi_offset = r.psi_g_rad - (*it)->yaw_rad;
    aligned = true;
    break;
  }
  for (size_t i = 0; i < truth.size(); ++i) {
    truth_rho[i] += rho_offset;
    truth_psi[i] += psi_offset;
    truth_x.push_back(truth_r[i] * std::cos(truth_rho[i]));
    truth_y.push_back(truth_r[i] * std::sin(truth_rho[i]));
  }
  unwrap(truth_rho);
  unwrap(truth_psi);

  struct Track {
    std::string name;
    const char* colour;
    std::span<const EstimateRow> rows;
    bool dashed;
  };
  std::vector<Track> tracks = {{"fused (estimates.csv)", kEstimateColour, run.rows, false}};
  if (!run.published.empty()) {
    tracks.push_back({"published node", kPublishedColour, run.published, false});
  }
  struct Quantity {
    const char* title;
    const char* unit;
    double EstimateRow::*value;
    bool angle;
    const std::vector<double>* truth;
  };
  const Quantity quantities[] = {
      {"r_g: distance from the pen axis", "m", &EstimateRow::r_g_m, false, &truth_r},
      {"rho_g: azimuth in the pen", "deg", &EstimateRow::rho_g_rad, true, &truth_rho},
      {"z_g: depth", "m", &EstimateRow::z_g_m, false, &truth_z},
      {"psi_g: yaw in the pen", "deg", &EstimateRow::psi_g_rad, true, &truth_psi}};
  for (const Quantity& q : quantities) {
    Chart c;
    c.title = q.title;
    c.x_label = "time [s]";
    c.y_label = q.unit;
    for (const Track& tr : tracks) {
      std::vector<double> y =
          column<EstimateRow>(tr.rows, [&](const EstimateRow& r) { return r.*q.value; });
      if (q.angle) unwrap(y);
      for (double& v : y) v = q.angle ? rad_to_deg(v) : v;
      c.series.push_back({tr.name, tr.colour, run.times(tr.rows), std::move(y), tr.dashed});
    }
    if (!truth.empty()) {
      std::vector<double> y = *q.truth;
      for (double& v : y) v = q.angle ? rad_to_deg(v) : v;
      c.series.push_back({"truth", kTruthColour, t_truth, std::move(y), true});
    }
    html += svg(c);
  }

  // Two views from above: the whole pen, and the track itself with the net's arc beside it.
  Chart pen;
  pen.title = "Track in the pen, seen from above";
  pen.x_label = "x = r_g cos rho_g [m]";
  pen.y_label = "y = r_g sin rho_g [m]";
  pen.equal_aspect = true;
  pen.width = pen.height = 490;
  if (run.in.dataset) {
    // A flat net is a pen of a large radius (dataset-format.md): then only its arc is drawn.
    pen.circle_radius_m = run.in.dataset->scene.pen_radius_m;
    pen.fit_circle = pen.circle_radius_m <= 30;
    pen.series.push_back({"net", kPenColour, {}, {}, false});
  }
  for (const Track& tr : tracks) {
    std::vector<double> x, y;
    for (const EstimateRow& r : tr.rows) {
      x.push_back(r.r_g_m * std::cos(r.rho_g_rad));
      y.push_back(r.r_g_m * std::sin(r.rho_g_rad));
    }
    pen.series.push_back({tr.name, tr.colour, std::move(x), std::move(y), tr.dashed});
  }
  if (!truth.empty()) pen.series.push_back({"truth", kTruthColour, truth_x, truth_y, true});
  Chart track = pen;
  track.title = "The track, seen from above";
  track.fit_circle = false;
  track.min_span_m = 2;
  html += "<div class=\"pair\">\n" + svg(pen) + svg(track) + "</div>\n";
  html +=
      "<p>Seen from above: the pen frame's z points down, into the page, so x to the right "
      "and y down the page turn clockwise, as yaw does.</p>\n";

  std::vector<std::string> notes;
  if (!run.in.published)
    notes.push_back("published node: " + not_written(kPublishedGlobalPoseFile));
  if (!truth.empty()) {
    notes.push_back(aligned ? "truth rho and yaw shifted by " +
                                  printf_double("%.1f", rad_to_deg(rho_offset)) + " and " +
                                  printf_double("%.1f", rad_to_deg(psi_offset)) +
                                  " deg to agree at the first frame with rho_g and psi_g (the "
                                  "pen's azimuth origin is not observable)"
                            : "no frame with rho_g and psi_g: truth azimuth and yaw as recorded");
  }
  if (!run.in.dataset) notes.push_back("no dataset given: no pen circle");
  std::string joined;
  for (const std::string& n : notes) joined += (joined.empty() ? "" : "; ") + n;
  if (!joined.empty()) html += not_available(joined);
  return html;
}

std::string evaluation_section(const Run& run) {
  std::string html = "<h2>Errors against the ground truth (pensight evaluate)</h2>\n";
  if (!run.in.dataset) return html + not_available("No dataset given: no ground truth");
  if (!run.truth) return html + not_available("The dataset has no groundtruth0/");
  const AccuracyEnvelope envelope;
  html += "<pre>" +
          html_escape(
              printf_double("measurable: net fraction >= %.2f, ", envelope.min_net_fraction) +
              printf_double("%.1f", envelope.min_d_net_m) + "-" +
              printf_double("%.1f m, ", envelope.max_d_net_m) +
              printf_double("|psi_net| <= %.0f deg\n", rad_to_deg(envelope.max_abs_psi_net_rad)) +
              "net pose from FFT:\n" +
              describe(score_net_pose(*run.in.dataset, run.rows, NetPoseSource::kFft, envelope)) +
              "global pose (all frames; rho_g and psi_g as changes from the first frame with "
              "both):\n" +
              describe(score_global_pose(*run.in.dataset, run.rows)));
  if (!run.published.empty()) {
    html += html_escape(std::string("global pose of the published node (") +
                        kPublishedGlobalPoseFile + ", the baseline):\n" +
                        describe(score_global_pose(*run.in.dataset, run.published)));
  }
  return html + "</pre>\n";
}

std::string diagnostics_section(const Run& run) {
  std::string html = "<h2>Diagnostics</h2>\n";
  if (!run.in.diagnostics) return html + not_available(not_written(kDiagnosticsFile));
  const std::vector<DiagnosticsRow>& rows = *run.in.diagnostics;
  std::map<std::string, size_t> reasons;
  for (const DiagnosticsRow& d : rows) {
    if (!d.fft_reason.empty()) ++reasons[d.fft_reason];
  }
  size_t nan_frames = 0;
  for (const auto& [reason, count] : reasons) nan_frames += count;
  html += "<p>" + std::to_string(rows.size()) + " frames, " + std::to_string(nan_frames) +
          " with the FFT pose NaN.</p>\n";
  if (!reasons.empty()) {
    std::vector<std::pair<std::string, size_t>> sorted(reasons.begin(), reasons.end());
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    html += "<table><tr><th>why the FFT pose is NaN (fft_reason)</th><th>frames</th></tr>\n";
    for (const auto& [reason, count] : sorted) {
      html += "<tr><td>" + html_escape(reason) + "</td><td class=\"n\">" + std::to_string(count) +
              "</td></tr>\n";
    }
    html += "</table>\n";
  }
  // The estimator's outcome per sensor, summed over the frames.
  html += "<table><tr><th>sensor</th><th>accepted</th><th>rejected</th></tr>\n";
  for (size_t i = 0; i < kDiagnosticsSensors.size(); ++i) {
    double accepted = 0, rejected = 0;
    for (const DiagnosticsRow& d : rows) {
      accepted += d.accepted[i];
      rejected += d.rejected[i];
    }
    html += "<tr><td>" + html_escape(kDiagnosticsSensors[i]) + "</td><td class=\"n\">" +
            short_number(accepted) + "</td><td class=\"n\">" + short_number(rejected) +
            "</td></tr>\n";
  }
  html += "</table>\n";
  Chart c;
  c.title = "ROIs per frame";
  c.x_label = "time [s]";
  c.y_label = "ROIs";
  c.height = 200;
  const std::vector<double> ts = column<DiagnosticsRow>(
      rows, [&](const DiagnosticsRow& d) { return run.seconds(d.timestamp_ns); });
  c.series.push_back({"with a lattice (valid_rois)", kEstimateColour, ts,
                      column<DiagnosticsRow>(rows, [](const DiagnosticsRow& d) {
                        return static_cast<double>(d.valid_rois);
                      })});
  c.series.push_back({"inliers of the pose (inlier_rois)", "#2a2", ts,
                      column<DiagnosticsRow>(rows, [](const DiagnosticsRow& d) {
                        return static_cast<double>(d.inlier_rois);
                      })});
  return html + svg(c);
}

// The columns of timing.csv, labelled for a reader, after the node's name.
struct TimingColumn {
  const char* label;
  double (*value)(const TimingRow&);
};
constexpr TimingColumn kTimingColumns[] = {
    {"count", [](const TimingRow& r) { return static_cast<double>(r.ours.processed); }},
    {"mean [ms]", [](const TimingRow& r) { return r.ours.mean_ms; }},
    {"p95 [ms]", [](const TimingRow& r) { return r.ours.p95_ms; }},
    {"max [ms]", [](const TimingRow& r) { return r.ours.max_ms; }},
    {"rate [Hz]", [](const TimingRow& r) { return r.ours.rate_hz; }},
    {"latency mean [ms]", [](const TimingRow& r) { return r.ours.latency_mean_ms; }},
    {"latency p95 [ms]", [](const TimingRow& r) { return r.ours.latency_p95_ms; }},
    {"published (Orin) mean [ms]", [](const TimingRow& r) { return r.published_ms; }},
    {"published rate [Hz]", [](const TimingRow& r) { return r.published_rate_hz; }}};

std::string timing_section(const Run& run) {
  std::string html = "<h2>Per-stage timing</h2>\n";
  if (!run.in.timing) return html + not_available(not_written(kTimingFile));
  html += "<table><tr><th>node</th>";
  for (const TimingColumn& c : kTimingColumns) html += std::string("<th>") + c.label + "</th>";
  html += "</tr>\n";
  for (const TimingRow& row : *run.in.timing) {
    html += "<tr><td>" + html_escape(row.ours.name) + "</td>";
    for (const TimingColumn& c : kTimingColumns) {
      html += "<td class=\"n\">" + short_number(c.value(row)) + "</td>";
    }
    html += "</tr>\n";
  }
  return html + "</table>\n";
}

// An overlay as the page embeds it: JPEG at quality 85, as a noisy 720x540 frame is ~0.7 MB as
// PNG and ~0.1 MB as JPEG with its lines and text still legible. A PNG OpenCV cannot decode is
// embedded as it is, so the page's self-check reports it as a broken image.
std::pair<std::string, std::string> embeddable(const std::filesystem::path& png) {
  const std::string bytes = read_file_bytes(png).value_or("");
  const cv::Mat image = cv::imdecode(
      cv::Mat(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<char*>(bytes.data())),
      cv::IMREAD_COLOR);
  std::vector<uchar> jpeg;
  if (image.empty() || !cv::imencode(".jpg", image, jpeg, {cv::IMWRITE_JPEG_QUALITY, 85})) {
    return {"image/png", bytes};
  }
  return {"image/jpeg", std::string(jpeg.begin(), jpeg.end())};
}

std::string overlays_section(const Run& run) {
  std::string html = "<h2>Overlay frames</h2>\n";
  const std::filesystem::path dir = run.in.out_dir / "overlays";
  std::vector<std::filesystem::path> files;
  if (std::filesystem::is_directory(dir)) {
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      if (entry.is_regular_file() && entry.path().extension() == ".png") {
        files.push_back(entry.path());
      }
    }
  }
  if (files.empty()) return html + not_available("overlays/*.png were not written by this run");
  std::sort(files.begin(), files.end());
  // Up to four, evenly spaced over the run, first and last included.
  const size_t shown = std::min<size_t>(4, files.size());
  html += "<p>" + std::to_string(shown) + " of the " + std::to_string(files.size()) +
          " overlays in overlays/. Squares: the ROIs (green: inlier of the pose, orange: valid but "
          "not an inlier, red: no usable lattice); parallelograms: cells of each ROI's lattice."
          "</p>\n<div class=\"overlays\">\n";
  for (size_t k = 0; k < shown; ++k) {
    const size_t i = shown == 1 ? 0 : k * (files.size() - 1) / (shown - 1);
    const auto [mime, bytes] = embeddable(files[i]);
    const std::string name = html_escape(files[i].filename().string());
    html += "<figure><img src=\"data:" + mime + ";base64," + base64(bytes) + "\" alt=\"" + name +
            "\"><figcaption>" + name + "</figcaption></figure>\n";
  }
  return html + "</div>\n";
}

std::string summary_section(const Run& run) {
  size_t fft = 0, global = 0;
  for (const EstimateRow& r : run.rows) {
    fft += std::isfinite(r.d_net_fft_m);
    global += std::isfinite(r.r_g_m);
  }
  const double span_s = run.rows.empty() ? 0 : run.seconds(run.rows.back().timestamp_ns);
  std::string html =
      "<p>Output folder: <code>" + html_escape(run.in.out_dir.string()) + "</code><br>\n";
  if (!run.in.input.empty()) {
    html += "Input: <code>" + html_escape(run.in.input.string()) +
            "</code> (converted to the dataset layout for the run)";
  } else {
    html += run.in.dataset
                ? "Dataset: <code>" + html_escape(run.in.dataset->root.string()) + "</code>"
                : std::string("Dataset: none given (no ground truth)");
  }
  html += "<br>\n" + std::to_string(run.rows.size()) + " frames over " +
          printf_double("%.1f", span_s) + " s (time 0: the first frame, timestamp " +
          std::to_string(run.t0_ns) + " ns); FFT net pose in " + std::to_string(fft) +
          ", global pose in " + std::to_string(global) + ".</p>\n";
  return html;
}

// The page checks itself once loaded: every image decoded and no script error. It marks the
// result on <html data-self-check="ok|..."> for tests in a headless browser and for a reader's
// developer console; the page's title stays the run's.
constexpr const char* kSelfCheck = R"(<script>
(function () {
  var problems = [];
  window.addEventListener('error', function (e) {
    problems.push(e.message || ('cannot load ' + ((e.target && e.target.alt) || 'a resource')));
  }, true);
  window.addEventListener('load', function () {
    for (var i = 0; i < document.images.length; ++i) {
      var img = document.images[i];
      if (!img.complete || img.naturalWidth === 0) problems.push('broken image ' + img.alt);
    }
    document.documentElement.setAttribute('data-self-check',
        problems.length ? 'failed: ' + problems.join('; ') : 'ok');
  });
})();
</script>
)";

constexpr const char* kStyle = R"(<style>
body { font-family: sans-serif; max-width: 1000px; margin: 1em auto; padding: 0 1em; color: #222; }
h2 { border-bottom: 1px solid #ccc; padding-bottom: 0.2em; margin-top: 1.6em; }
svg { display: block; margin: 0.6em 0; max-width: 100%; height: auto; }
table { border-collapse: collapse; margin: 0.6em 0; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; }
td.n { text-align: right; font-variant-numeric: tabular-nums; }
pre { background: #f4f4f4; padding: 0.8em; overflow-x: auto; }
.absent { color: #777; font-style: italic; }
.pair { display: flex; gap: 0.5em; flex-wrap: wrap; }
.overlays { display: grid; grid-template-columns: 1fr 1fr; gap: 0.8em; }
figure { margin: 0; } figure img { width: 100%; height: auto; display: block; }
figcaption { font-size: 0.85em; color: #555; }
</style>
)";

}  // namespace

void write_report_html(const ReportInput& input) {
  const std::filesystem::path& out_dir = input.out_dir;
  if (!input.estimates) {
    throw Error("report for '" + out_dir.string() +
                "': no estimates; `pensight run DATASET --out " + out_dir.string() +
                "` produces them (estimates.csv), run that first");
  }
  Run run{input, *input.estimates, {}, 0, nullptr};
  if (input.published) run.published = *input.published;
  if (!run.rows.empty()) run.t0_ns = run.rows.front().timestamp_ns;
  if (input.dataset && input.dataset->groundtruth0) run.truth = &*input.dataset->groundtruth0;

  std::string html =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>pensight "
      "report: " +
      html_escape(out_dir.filename().empty() ? out_dir.parent_path().filename().string()
                                             : out_dir.filename().string()) +
      "</title>\n" + kSelfCheck + kStyle + "</head>\n<body>\n<h1>pensight run report</h1>\n";
  html += summary_section(run);
  html += net_pose_section(run);
  html += global_pose_section(run);
  html += evaluation_section(run);
  html += diagnostics_section(run);
  html += timing_section(run);
  html += overlays_section(run);
  html += "</body>\n</html>\n";
  write_file_atomically(out_dir / "report.html", html);
}

}  // namespace pensight
