#include "tools/report/overlay.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/units.h"

namespace pensight {
namespace {

// A ROI's part in the frame's pose, which its colour shows (BGR).
enum class RoiState { kInlier, kSecondPanel, kOtherTilt, kOutlier, kNoLattice };
const std::array<cv::Scalar, 5> kStateColour = {cv::Scalar(60, 210, 60), cv::Scalar(230, 200, 40),
                                                cv::Scalar(235, 120, 235), cv::Scalar(0, 165, 255),
                                                cv::Scalar(70, 70, 235)};
const std::array<const char*, 5> kStateLabel = {
    "inlier of the pose", "the other panel of a fold: left out",
    "on the net, tilted otherwise (rope, seam, fold): left out",
    "valid, off the net's surface: left out", "no usable lattice"};

RoiState state_of(const NetDetection& detection, size_t i) {
  if (!detection.points[i].valid()) return RoiState::kNoLattice;
  const FftRelativePose& pose = detection.pose;
  if (i < pose.inlier.size() && pose.inlier[i]) return RoiState::kInlier;
  if (i < pose.second_panel.size() && pose.second_panel[i]) return RoiState::kSecondPanel;
  if (i < pose.other_tilt.size() && pose.other_tilt[i]) return RoiState::kOtherTilt;
  return RoiState::kOutlier;
}

// cv::line and cv::polylines draw at sub-pixel positions with this many fractional bits.
constexpr int kShift = 4;
cv::Point fixed_point(const Eigen::Vector2d& p_px) {
  return {static_cast<int>(std::lround(p_px.x() * (1 << kShift))),
          static_cast<int>(std::lround(p_px.y() * (1 << kShift)))};
}

// 3 x 3 lattice cells: the parallelograms spanned by a1 and a2, the middle one centred on c.
void draw_cells(cv::Mat& image, const Eigen::Vector2d& c, const Eigen::Vector2d& a1,
                const Eigen::Vector2d& a2, const cv::Scalar& colour, int thickness) {
  for (int k = 0; k < 4; ++k) {
    const double u = k - 1.5;
    cv::line(image, fixed_point(c + u * a1 - 1.5 * a2), fixed_point(c + u * a1 + 1.5 * a2), colour,
             thickness, cv::LINE_AA, kShift);
    cv::line(image, fixed_point(c + u * a2 - 1.5 * a1), fixed_point(c + u * a2 + 1.5 * a1), colour,
             thickness, cv::LINE_AA, kShift);
  }
}

struct Font {
  int face = cv::FONT_HERSHEY_SIMPLEX;
  double scale = 0.5;
  int thickness = 1;
  int width(const std::string& s) const {
    int baseline = 0;
    return cv::getTextSize(s, face, scale, thickness, &baseline).width;
  }
  int line_height() const {
    int baseline = 0;
    return cv::getTextSize("Ag", face, scale, thickness, &baseline).height + baseline + 4;
  }
};

// Greedy word wrap to max_width pixels (a NaN reason can be longer than the frame is wide).
std::vector<std::string> wrap(const std::string& text, const Font& font, int max_width) {
  std::vector<std::string> lines;
  std::string line;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(start, end - start);
    const std::string candidate = line.empty() ? word : line + " " + word;
    if (!line.empty() && font.width(candidate) > max_width) {
      lines.push_back(line);
      line = word;
    } else {
      line = candidate;
    }
    start = end + 1;
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

// Text on a translucent dark box so it reads on bright and dark frames alike; `swatches` colours
// a square before each line when given (the legend).
void draw_text_box(cv::Mat& image, cv::Point top_left, const std::vector<std::string>& lines,
                   const Font& font, std::span<const cv::Scalar> swatches = {}) {
  const int h = font.line_height(), pad = h / 3, swatch = swatches.empty() ? 0 : h;
  int w = 0;
  for (const std::string& s : lines) w = std::max(w, font.width(s));
  const cv::Rect box(top_left.x, top_left.y, w + swatch + 2 * pad,
                     h * static_cast<int>(lines.size()) + 2 * pad);
  cv::Mat shaded = image.clone();
  cv::rectangle(shaded, box, cv::Scalar(0, 0, 0), cv::FILLED);
  cv::addWeighted(shaded, 0.6, image, 0.4, 0, image);
  for (size_t i = 0; i < lines.size(); ++i) {
    const int y = box.y + pad + h * static_cast<int>(i);
    if (i < swatches.size()) {
      cv::rectangle(image, cv::Rect(box.x + pad, y + h / 6, h * 2 / 3, h * 2 / 3), swatches[i],
                    cv::FILLED);
    }
    cv::putText(image, lines[i], cv::Point(box.x + pad + swatch, y + h - h / 4 - 2), font.face,
                font.scale, cv::Scalar(255, 255, 255), font.thickness, cv::LINE_AA);
  }
}

std::string pose_text(const FftRelativePose& pose) {
  if (!pose.valid()) return "FFT pose NaN: " + pose.reason;
  char buf[160];
  std::snprintf(buf, sizeof buf, "d_net %.3f m   psi_net %.1f deg   pitch_net %.1f deg",
                pose.d_net_m, rad_to_deg(pose.psi_net_rad), rad_to_deg(pose.pitch_net_rad));
  return buf;
}

}  // namespace

void write_overlay_png(const std::filesystem::path& file, const ImageU8& frame,
                       const NetDetection& detection) {
  const std::vector<kernels::RoiOrigin>& rois = detection.rois;
  const int roi_size_px = detection.roi_size_px;
  if (frame.empty()) throw Error("overlay '" + file.string() + "': the frame is empty");
  if (detection.points.size() != rois.size()) {
    throw Error("overlay '" + file.string() + "': the detection has " +
                std::to_string(detection.points.size()) + " points but " +
                std::to_string(rois.size()) + " ROIs; pass a NetDetector::detect() result");
  }
  cv::Mat image;
  cv::cvtColor(
      cv::Mat(frame.height, frame.width, CV_8UC1, const_cast<uint8_t*>(frame.pixels.data())), image,
      cv::COLOR_GRAY2BGR);

  // The default grid's ROIs overlap (6 x 300 px across 720 px), so their squares are thin and
  // translucent; the lattice cells, one set per ROI, are drawn solid over them.
  cv::Mat squares = image.clone();
  for (size_t i = 0; i < rois.size(); ++i) {
    const cv::Scalar& colour = kStateColour[static_cast<int>(state_of(detection, i))];
    cv::rectangle(squares, cv::Rect(rois[i].x, rois[i].y, roi_size_px, roi_size_px), colour, 1);
  }
  cv::addWeighted(squares, 0.7, image, 0.3, 0, image);
  const int thickness = std::max(1, frame.width / 500);
  for (size_t i = 0; i < rois.size(); ++i) {
    const RoiNetPoint& p = detection.points[i];
    const cv::Scalar& colour = kStateColour[static_cast<int>(state_of(detection, i))];
    cv::circle(image, fixed_point(p.centre_px), 3 << kShift, colour, cv::FILLED, cv::LINE_AA,
               kShift);
    // The geometry stage sets the lattice vectors for every ROI whose lattice it measured (also
    // those it then rejects as too fine or too oblique); they are centred where it was measured.
    if (p.lattice1_px.isZero() || p.lattice2_px.isZero()) continue;
    draw_cells(image, p.centre_px, p.lattice1_px, p.lattice2_px, colour, thickness);
  }

  Font font;
  font.scale = std::max(0.4, frame.width / 1300.0);
  const int margin = std::max(4, frame.width / 150);
  std::vector<std::string> lines = wrap(pose_text(detection.pose), font, frame.width * 3 / 4);
  lines.push_back(std::to_string(detection.pose.valid_rois) + " of " + std::to_string(rois.size()) +
                  " ROIs with a lattice, " + std::to_string(detection.pose.inlier_rois) +
                  " inliers");
  lines.push_back("t " + std::to_string(detection.timestamp_ns) + " ns");
  draw_text_box(image, cv::Point(margin, margin), lines, font);
  const std::vector<std::string> legend(kStateLabel.begin(), kStateLabel.end());
  draw_text_box(image,
                cv::Point(margin, frame.height - margin -
                                      static_cast<int>(legend.size()) * font.line_height() -
                                      2 * (font.line_height() / 3)),
                legend, font, kStateColour);

  std::vector<uchar> bytes;
  if (!cv::imencode(".png", image, bytes)) {
    throw Error("cannot encode overlay '" + file.string() + "' as PNG");
  }
  write_file_atomically(
      file, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace pensight
