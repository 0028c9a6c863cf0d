#include "tools/report/svg_chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace pensight {
namespace {

struct Axis {
  double lo = 0, hi = 1;
  std::vector<double> ticks;
};

// Covers [lo, hi] with ticks at 1, 2 or 5 times a power of ten.
Axis nice_axis(double lo, double hi) {
  if (!(lo <= hi)) lo = 0, hi = 1;
  if (hi - lo < 1e-9 * std::max(1.0, std::abs(lo))) lo -= 0.5, hi += 0.5;
  const double raw = (hi - lo) / 5, magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10 * magnitude;
  for (const double m : {1.0, 2.0, 5.0}) {
    if (m * magnitude >= raw) {
      step = m * magnitude;
      break;
    }
  }
  Axis a{std::floor(lo / step) * step, std::ceil(hi / step) * step, {}};
  for (int k = 0; a.lo + k * step <= a.hi + 0.5 * step; ++k) {
    const double t = a.lo + k * step;
    a.ticks.push_back(std::abs(t) < 1e-9 * step ? 0 : t);  // never "-0"
  }
  return a;
}

// As many decimals as the tick step needs (0.05 -> 2).
std::string tick_label(double t, const Axis& a) {
  const double step = a.ticks.size() > 1 ? a.ticks[1] - a.ticks[0] : 1;
  const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, t);
  return buf;
}

}  // namespace

std::string html_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string printf_double(const char* spec, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, spec, v);
  return buf;
}

std::string svg(const Chart& c) {
  constexpr double kLeft = 64, kRight = 16, kBottom = 40;
  // Legend entries left to right under the title, wrapping to more rows; the plot starts below.
  std::vector<std::pair<double, double>> legend_at;
  double legend_x = kLeft, legend_y = 30;
  for (const Series& s : c.series) {
    const double w = 45 + 6.5 * static_cast<double>(s.name.size());
    if (legend_x > kLeft && legend_x + w > c.width - kRight) legend_x = kLeft, legend_y += 16;
    legend_at.emplace_back(legend_x, legend_y);
    legend_x += w;
  }
  const double top = legend_y + 14;
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
  for (const Series& s : c.series) {
    for (size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x_lo = std::min(x_lo, s.x[i]), x_hi = std::max(x_hi, s.x[i]);
      y_lo = std::min(y_lo, s.y[i]), y_hi = std::max(y_hi, s.y[i]);
    }
  }
  const double plot_w = c.width - kLeft - kRight, plot_h = c.height - top - kBottom;
  if (c.equal_aspect) {
    if (c.fit_circle) {
      x_lo = std::min(x_lo, -c.circle_radius_m), x_hi = std::max(x_hi, c.circle_radius_m);
      y_lo = std::min(y_lo, -c.circle_radius_m), y_hi = std::max(y_hi, c.circle_radius_m);
    }
    if (!(x_lo <= x_hi)) x_lo = y_lo = -1, x_hi = y_hi = 1;
    // Both axes span the same metres per pixel, centred on the data, with a margin of 10 %.
    const double m_per_px = std::max({(x_hi - x_lo) / plot_w, (y_hi - y_lo) / plot_h,
                                      c.min_span_m / std::min(plot_w, plot_h)}) *
                                1.2 +
                            1e-9;
    const double xc = 0.5 * (x_lo + x_hi), yc = 0.5 * (y_lo + y_hi);
    x_lo = xc - 0.5 * m_per_px * plot_w, x_hi = xc + 0.5 * m_per_px * plot_w;
    y_lo = yc - 0.5 * m_per_px * plot_h, y_hi = yc + 0.5 * m_per_px * plot_h;
  }
  Axis xa = nice_axis(x_lo, x_hi), ya = nice_axis(y_lo, y_hi);
  if (c.equal_aspect) {
    // Keep the equal scale: the ticks fall inside, the range stays as computed.
    std::erase_if(xa.ticks, [&](double t) { return t < x_lo || t > x_hi; });
    std::erase_if(ya.ticks, [&](double t) { return t < y_lo || t > y_hi; });
    xa.lo = x_lo, xa.hi = x_hi, ya.lo = y_lo, ya.hi = y_hi;
  }
  // Top views are seen from above with P's z down: x to the right and y down the page turn
  // clockwise, as yaw does. Time charts put y up.
  const auto px = [&](double x) { return kLeft + (x - xa.lo) / (xa.hi - xa.lo) * plot_w; };
  const auto py = [&](double y) {
    const double f = (y - ya.lo) / (ya.hi - ya.lo);
    return top + (c.equal_aspect ? f : 1 - f) * plot_h;
  };

  std::ostringstream o;
  o << "<svg width=\"" << c.width << "\" height=\"" << c.height << "\" viewBox=\"0 0 " << c.width
    << " " << c.height << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
    << "<text x=\"" << kLeft << "\" y=\"16\" font-weight=\"bold\">" << html_escape(c.title)
    << "</text>\n";
  for (size_t i = 0; i < c.series.size(); ++i) {
    const Series& s = c.series[i];
    const auto [x, y] = legend_at[i];
    o << "<line x1=\"" << x << "\" y1=\"" << y << "\" x2=\"" << x + 22 << "\" y2=\"" << y
      << "\" stroke=\"" << s.colour << "\" stroke-width=\"2\""
      << (s.dashed ? " stroke-dasharray=\"5 3\"" : "") << "/><text x=\"" << x + 27 << "\" y=\""
      << y + 4 << "\">" << html_escape(s.name) << "</text>\n";
  }
  o << "<rect x=\"" << kLeft << "\" y=\"" << top << "\" width=\"" << plot_w << "\" height=\""
    << plot_h << "\" fill=\"#fafafa\" stroke=\"#999\"/>\n";
  for (const double t : xa.ticks) {
    o << "<line x1=\"" << px(t) << "\" y1=\"" << top << "\" x2=\"" << px(t) << "\" y2=\""
      << top + plot_h << "\" stroke=\"#e4e4e4\"/><text x=\"" << px(t) << "\" y=\""
      << top + plot_h + 15 << "\" text-anchor=\"middle\">" << tick_label(t, xa) << "</text>\n";
  }
  for (const double t : ya.ticks) {
    o << "<line x1=\"" << kLeft << "\" y1=\"" << py(t) << "\" x2=\"" << kLeft + plot_w << "\" y2=\""
      << py(t) << "\" stroke=\"#e4e4e4\"/><text x=\"" << kLeft - 5 << "\" y=\"" << py(t) + 4
      << "\" text-anchor=\"end\">" << tick_label(t, ya) << "</text>\n";
  }
  o << "<text x=\"" << kLeft + plot_w / 2 << "\" y=\"" << c.height - 6
    << "\" text-anchor=\"middle\">" << html_escape(c.x_label) << "</text>\n"
    << "<text transform=\"translate(14," << top + plot_h / 2
    << ") rotate(-90)\" text-anchor=\"middle\">" << html_escape(c.y_label) << "</text>\n";
  // A nested viewport in the outer coordinates clips what lies beyond the axes (the pen circle).
  o << "<svg x=\"" << kLeft << "\" y=\"" << top << "\" width=\"" << plot_w << "\" height=\""
    << plot_h << "\" viewBox=\"" << kLeft << " " << top << " " << plot_w << " " << plot_h
    << "\">\n";
  if (std::isfinite(c.circle_radius_m)) {
    o << "<circle cx=\"" << px(0) << "\" cy=\"" << py(0) << "\" r=\""
      << c.circle_radius_m / (xa.hi - xa.lo) * plot_w << "\" fill=\"none\" stroke=\"" << kPenColour
      << "\" stroke-width=\"2\"/>\n";
  }
  for (const Series& s : c.series) {
    // One path per run of finite points; a lone point between NaNs gets a dot.
    std::string path;
    size_t run = 0;
    for (size_t i = 0; i <= s.x.size(); ++i) {
      const bool ok = i < s.x.size() && std::isfinite(s.x[i]) && std::isfinite(s.y[i]);
      if (ok) {
        path += run == 0 ? 'M' : 'L';
        path += printf_double("%.1f", px(s.x[i]));
        path += ',';
        path += printf_double("%.1f", py(s.y[i]));
        ++run;
        continue;
      }
      if (run == 1) {
        o << "<circle cx=\"" << px(s.x[i - 1]) << "\" cy=\"" << py(s.y[i - 1])
          << "\" r=\"1.8\" fill=\"" << s.colour << "\"/>\n";
      }
      run = 0;
    }
    if (!path.empty()) {
      o << "<path d=\"" << path << "\" fill=\"none\" stroke=\"" << s.colour
        << "\" stroke-width=\"1.5\"" << (s.dashed ? " stroke-dasharray=\"5 3\"" : "") << "/>\n";
    }
  }
  o << "</svg></svg>\n";
  return o.str();
}

}  // namespace pensight
