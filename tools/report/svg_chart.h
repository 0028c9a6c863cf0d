#pragma once
// Inline SVG line charts for the self-contained HTML reports (OUT/report.html, the closed loop's
// OUT/closed_loop.html): axes with round ticks, a legend, NaN breaking a line, and top views at
// one scale on both axes with the pen circle.
#include <string>
#include <string_view>
#include <vector>

#include "core/units.h"

namespace pensight {

struct Series {
  std::string name;
  std::string colour;
  std::vector<double> x, y;  // a non-finite point breaks the line
  bool dashed = false;
};

struct Chart {
  std::string title;
  std::string x_label, y_label;
  std::vector<Series> series;
  bool equal_aspect = false;      // top views: one metre is as long on both axes
  double circle_radius_m = kNaN;  // the pen, centred on the origin
  bool fit_circle = false;        // the axes cover the whole circle, not only the data
  double min_span_m = 0;          // equal_aspect: the axes cover at least this much
  int width = 960, height = 250;
};

inline constexpr const char* kPenColour = "#3a9a6a";  // the pen circle in top views

// The chart as one <svg> element (pixel size c.width x c.height).
std::string svg(const Chart& c);

// Text for HTML: & < > " ' escaped.
std::string html_escape(std::string_view s);
// One number through printf's `spec` ("%.1f").
std::string printf_double(const char* spec, double v);

}  // namespace pensight
