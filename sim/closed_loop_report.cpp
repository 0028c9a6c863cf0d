#include "sim/closed_loop_report.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/units.h"
#include "tools/report/svg_chart.h"

namespace pensight::sim {

ClosedLoopMetrics closed_loop_metrics(const std::vector<ClosedLoopStep>& steps, double settle_s) {
  ClosedLoopMetrics m;
  double distance_sq = 0, heading_sq = 0;
  int heading_n = 0;
  for (size_t i = 0; i < steps.size(); ++i) {
    const ClosedLoopStep& st = steps[i];
    const control::ControlOutput& c = st.command;
    if (std::isfinite(st.d_net_true_m)) {
      m.min_distance_m = std::isnan(m.min_distance_m) ? st.d_net_true_m
                                                      : std::min(m.min_distance_m, st.d_net_true_m);
    }
    if (c.state == control::ControlState::kStartup) continue;
    if (m.legs.empty() || m.legs.back().leg != c.leg) {
      LegMetrics leg;
      leg.leg = c.leg;
      leg.start_s = st.t_s;
      leg.d_ref_m = c.d_ref_m;
      leg.step_m = c.d_ref_m - st.d_net_true_m;
      m.legs.push_back(leg);
    }
    LegMetrics& leg = m.legs.back();
    const double error = st.d_net_true_m - leg.d_ref_m;
    if (std::isfinite(error)) {
      const double band = std::max(0.05, 0.1 * std::abs(leg.step_m));
      if (std::abs(error) > band) {
        leg.settle_s = kNaN;
      } else if (std::isnan(leg.settle_s)) {
        leg.settle_s = st.t_s - leg.start_s;
      }
      if (leg.step_m != 0)
        leg.overshoot_m = std::max(leg.overshoot_m, error * (leg.step_m > 0 ? 1 : -1));
    }
    if (c.state != control::ControlState::kTracking || st.t_s - leg.start_s < settle_s) continue;
    if (std::isfinite(error)) {
      distance_sq += error * error;
      ++m.settled_steps;
    }
    const double heading_error = rad_to_deg(wrap_angle(st.psi_net_true_rad - c.heading_ref_rad));
    if (std::isfinite(heading_error)) {
      heading_sq += heading_error * heading_error;
      ++heading_n;
    }
  }
  if (m.settled_steps > 0) m.distance_rmse_m = std::sqrt(distance_sq / m.settled_steps);
  if (heading_n > 0) m.heading_rmse_deg = std::sqrt(heading_sq / heading_n);
  return m;
}

void write_closed_loop_csv(const std::filesystem::path& file,
                           const std::vector<ClosedLoopStep>& steps) {
  AtomicFile f(file);
  std::ostream& o = f.stream();
  o << "#timestamp [ns],d_net_true [m],psi_net_true [rad],d_net_est [m],psi_net_est [rad],"
       "d_ref [m],heading_ref [rad],depth_true [m],depth_ref [m],along_true [m],u_true [m/s],"
       "v_true [m/s],state,strategy,leg,u_ref [m/s],v_ref [m/s],r_ref [rad/s],climb_ref [m/s],"
       "surge_force [N],sway_force [N],stick_x,stick_y,stick_z,stick_r\n";
  for (const ClosedLoopStep& s : steps) {
    const control::ControlOutput& c = s.command;
    o << s.timestamp_ns;
    for (const double v :
         {s.d_net_true_m, s.psi_net_true_rad, s.d_net_est_m, s.psi_net_est_rad, c.d_ref_m,
          c.heading_ref_rad, s.depth_true_m, c.depth_ref_m, s.along_true_m,
          s.velocity_body_true_mps.x(), s.velocity_body_true_mps.y()}) {
      o << ',' << format_number(v);
    }
    o << ',' << control::to_string(c.state) << ',' << control::to_string(c.strategy) << ','
      << c.leg;
    for (const double v : {c.u_ref_mps, c.v_ref_mps, c.r_ref_radps, c.climb_ref_mps,
                           c.surge_force_n, c.sway_force_n, c.x, c.y, c.z, c.r}) {
      o << ',' << format_number(v);
    }
    o << '\n';
  }
  f.commit();
}

namespace {

Series series(const std::vector<ClosedLoopStep>& steps, const std::string& name,
              const std::string& colour, double (*value)(const ClosedLoopStep&),
              bool dashed = false) {
  Series s{name, colour, {}, {}, dashed};
  for (const ClosedLoopStep& st : steps) {
    s.x.push_back(st.t_s);
    s.y.push_back(value(st));
  }
  return s;
}

std::string number(double v, const char* spec = "%.3g") {
  return std::isfinite(v) ? printf_double(spec, v) : "n/a";
}

}  // namespace

void write_closed_loop_html(const std::filesystem::path& file, const Scenario& s,
                            const ClosedLoopSummary& summary) {
  const auto& steps = summary.steps;
  const ClosedLoopMetrics m = closed_loop_metrics(steps);
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>pensight closed loop: "
    << html_escape(s.name)
    << "</title><style>body{font-family:sans-serif;max-width:1000px;margin:1em auto}"
       "td,th{padding:2px 10px;text-align:right}svg{display:block;max-width:100%;height:auto}"
       "</style></head><body>\n<h1>Closed loop: "
    << html_escape(s.name) << "</h1>\n<p>"
    << html_escape(std::string("strategy ") +
                   (steps.empty() ? "" : control::to_string(s.control->strategy)) + "; renderer " +
                   summary.renderer + "; perception " + summary.backend)
    << ". " << number(summary.simulated_s, "%.1f") << " s simulated in "
    << number(summary.wall_s, "%.1f") << " s ("
    << number(summary.simulated_s / std::max(summary.wall_s, 1e-9), "%.2f")
    << "x real time).</p>\n<table><tr><th>distance RMSE after settling</th><th>heading RMSE</th>"
       "<th>nearest to the net</th><th>hold / back-off / open-loop steps</th><th>recoveries</th>"
       "</tr><tr><td>"
    << number(100 * m.distance_rmse_m) << " cm</td><td>" << number(m.heading_rmse_deg)
    << " deg</td><td>" << number(m.min_distance_m) << " m</td><td>" << summary.counters.hold_steps
    << " / " << summary.counters.backoff_steps << " / " << summary.counters.open_loop_fallback_steps
    << "</td><td>" << summary.counters.recoveries
    << "</td></tr></table>\n<table><tr><th>leg</th><th>start [s]</th><th>d_ref [m]</th>"
       "<th>step [m]</th><th>settled after [s]</th><th>overshoot [cm]</th></tr>\n";
  for (const LegMetrics& l : m.legs) {
    h << "<tr><td>" << l.leg << "</td><td>" << number(l.start_s, "%.1f") << "</td><td>"
      << number(l.d_ref_m) << "</td><td>" << number(l.step_m) << "</td><td>"
      << number(l.settle_s, "%.1f") << "</td><td>" << number(100 * l.overshoot_m) << "</td></tr>\n";
  }
  h << "</table>\n";

  Chart distance{"Distance to the net (camera, along its axis)", "time [s]", "[m]", {}};
  distance.series = {
      series(steps, "truth", "#1f5fa8", [](const ClosedLoopStep& x) { return x.d_net_true_m; }),
      series(steps, "perception (FFT)", "#d07a18",
             [](const ClosedLoopStep& x) { return x.d_net_est_m; }),
      series(
          steps, "reference", "#444", [](const ClosedLoopStep& x) { return x.command.d_ref_m; },
          true)};
  Chart heading{"Heading to the net", "time [s]", "[deg]", {}};
  heading.series = {
      series(steps, "truth", "#1f5fa8",
             [](const ClosedLoopStep& x) { return rad_to_deg(x.psi_net_true_rad); }),
      series(steps, "perception (FFT)", "#d07a18",
             [](const ClosedLoopStep& x) { return rad_to_deg(x.psi_net_est_rad); }),
      series(
          steps, "reference", "#444",
          [](const ClosedLoopStep& x) { return rad_to_deg(x.command.heading_ref_rad); }, true)};
  Chart speed{"Speed over ground (body axes)", "time [s]", "[m/s]", {}};
  speed.series = {series(steps, "surge u", "#1f5fa8",
                         [](const ClosedLoopStep& x) { return x.velocity_body_true_mps.x(); }),
                  series(
                      steps, "u_ref", "#1f5fa8",
                      [](const ClosedLoopStep& x) { return x.command.u_ref_mps; }, true),
                  series(steps, "sway v", "#3a9a6a",
                         [](const ClosedLoopStep& x) { return x.velocity_body_true_mps.y(); }),
                  series(
                      steps, "v_ref", "#3a9a6a",
                      [](const ClosedLoopStep& x) { return x.command.v_ref_mps; }, true)};
  Chart sticks{"Commands (MANUAL_CONTROL sticks; z - 0.5)", "time [s]", "[-1, 1]", {}};
  sticks.series = {
      series(steps, "x", "#1f5fa8", [](const ClosedLoopStep& x) { return x.command.x; }),
      series(steps, "y", "#3a9a6a", [](const ClosedLoopStep& x) { return x.command.y; }),
      series(steps, "r", "#b03a2e", [](const ClosedLoopStep& x) { return x.command.r; }),
      series(steps, "z", "#777", [](const ClosedLoopStep& x) { return x.command.z - 0.5; })};
  Chart depth{"Depth", "time [s]", "[m]", {}};
  depth.series = {
      series(steps, "truth", "#1f5fa8", [](const ClosedLoopStep& x) { return x.depth_true_m; }),
      series(
          steps, "reference", "#444", [](const ClosedLoopStep& x) { return x.command.depth_ref_m; },
          true)};
  for (const Chart* c : {&distance, &heading, &speed, &sticks, &depth}) h << svg(*c);
  h << "<p>Files: closed_loop.csv (every step), the rendered dataset beside it (cam0/, "
       "groundtruth0/, dvl0/, pressure0/, imu0/).</p>\n</body></html>\n";
  write_file_atomically(file, h.str());
}

}  // namespace pensight::sim
