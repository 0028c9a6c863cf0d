#include <cmath>
#include <string>

#include "kernels/roi_normalize/roi_normalize.h"
#include "runtime/error.h"

namespace pensight::kernels {

void validate(const RoiNormalizeShape& s, std::span<const RoiOrigin> rois) {
  if (s.bits != 8 && s.bits != 16) {
    throw Error("roi_normalize: bits must be 8 or 16, got " + std::to_string(s.bits));
  }
  if (s.width <= 0 || s.height <= 0 || s.roi_size <= 0 || s.roi_size > s.width ||
      s.roi_size > s.height) {
    throw Error("roi_normalize: ROI size " + std::to_string(s.roi_size) + " does not fit a " +
                std::to_string(s.width) + "x" + std::to_string(s.height) + " image");
  }
  for (size_t i = 0; i < rois.size(); ++i) {
    const RoiOrigin& r = rois[i];
    if (r.x < 0 || r.y < 0 || r.x + s.roi_size > s.width || r.y + s.roi_size > s.height) {
      throw Error("roi_normalize: ROI " + std::to_string(i) + " at (" + std::to_string(r.x) + ", " +
                  std::to_string(r.y) + ") of size " + std::to_string(s.roi_size) + " leaves the " +
                  std::to_string(s.width) + "x" + std::to_string(s.height) + " image");
    }
  }
}

namespace {

template <class Pixel>
void normalize(const Image<Pixel>& image, std::span<const RoiOrigin> rois, int size,
               std::span<float> out) {
  validate({image.width, image.height, sizeof(Pixel) * 8, size}, rois);
  const size_t n = static_cast<size_t>(size) * size;
  if (out.size() < rois.size() * n) {
    throw Error("roi_normalize_cpu: output holds " + std::to_string(out.size()) + " floats, " +
                std::to_string(rois.size() * n) + " needed");
  }
  for (size_t r = 0; r < rois.size(); ++r) {
    const RoiOrigin o = rois[r];
    double sum = 0;
    for (int y = 0; y < size; ++y) {
      const Pixel* row = &image.at(o.x, o.y + y);
      for (int x = 0; x < size; ++x) sum += row[x];
    }
    const double mean = sum / static_cast<double>(n);
    double sq = 0;
    for (int y = 0; y < size; ++y) {
      const Pixel* row = &image.at(o.x, o.y + y);
      for (int x = 0; x < size; ++x) sq += (row[x] - mean) * (row[x] - mean);
    }
    const double var = sq / static_cast<double>(n);
    const double inv_std = var > kFlatVariance ? 1.0 / std::sqrt(var) : 0.0;
    float* dst = out.data() + r * n;
    for (int y = 0; y < size; ++y) {
      const Pixel* row = &image.at(o.x, o.y + y);
      for (int x = 0; x < size; ++x) {
        dst[static_cast<size_t>(y) * size + x] = static_cast<float>((row[x] - mean) * inv_std);
      }
    }
  }
}

}  // namespace

void roi_normalize_cpu(const ImageU8& image, std::span<const RoiOrigin> rois, int roi_size,
                       std::span<float> out) {
  normalize(image, rois, roi_size, out);
}

void roi_normalize_cpu(const ImageU16& image, std::span<const RoiOrigin> rois, int roi_size,
                       std::span<float> out) {
  normalize(image, rois, roi_size, out);
}

}  // namespace pensight::kernels
