// Exact nearest-point map in O(W*H + K*H): a column pass over the K columns that hold a point,
// then Felzenszwalb-Huttenlocher's lower envelope of parabolas along each row. Every key is
// kIndexBase * dist^2 + point index, so the envelope's minimum at an integer pixel is the unique
// lexicographic (distance, index) minimum: two parabolas can only meet between pixels, and the
// intersections are compared as exact rationals.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "kernels/sparse_prior/sparse_prior.h"
#include "kernels/sparse_prior/sparse_prior_detail.h"

namespace pensight::kernels {
namespace {

constexpr int64_t kIndexBase = 2048;  // > kMaxSparsePoints
static_assert(kIndexBase > kMaxSparsePoints);

struct Rational {
  int64_t num = 0;
  int64_t den = 1;  // > 0
};

// Calls fn(pixel index, point index or -1, squared distance) in row-major order.
template <class Fn>
void for_each_nearest(const SparsePriorShape& s, std::span<const SparsePoint> points, Fn&& fn) {
  const int w = s.width, h = s.height;
  if (points.empty()) {
    const int64_t d2 = detail::empty_dist2(s);
    for (size_t i = 0; i < static_cast<size_t>(w) * h; ++i) fn(i, -1, d2);
    return;
  }
  // Points by (column, row, index): within a column the first of equal rows has the lowest index.
  std::vector<std::array<int, 3>> sorted;
  sorted.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    sorted.push_back(
        {detail::snap(points[i].x_px), detail::snap(points[i].y_px), static_cast<int>(i)});
  }
  std::sort(sorted.begin(), sorted.end());

  std::vector<int> cols;
  for (const auto& p : sorted) {
    if (cols.empty() || cols.back() != p[0]) cols.push_back(p[0]);
  }
  const size_t k_cols = cols.size();
  // key[y * K + j]: best kIndexBase * dy^2 + index in column j at row y.
  std::vector<int64_t> key(k_cols * h);
  size_t begin = 0;
  for (size_t j = 0; j < k_cols; ++j) {
    size_t end = begin;
    while (end < sorted.size() && sorted[end][0] == cols[j]) ++end;
    size_t next = begin;  // first seed with row >= y
    for (int y = 0; y < h; ++y) {
      while (next < end && sorted[next][1] < y) ++next;
      int64_t best = std::numeric_limits<int64_t>::max();
      if (next < end) {
        const int64_t dy = sorted[next][1] - y;
        best = kIndexBase * dy * dy + sorted[next][2];
      }
      if (next > begin) {
        // The last seed above: the lowest index among those sharing its row is the first of them.
        size_t above = next - 1;
        while (above > begin && sorted[above - 1][1] == sorted[above][1]) --above;
        const int64_t dy = y - sorted[above][1];
        best = std::min(best, kIndexBase * dy * dy + sorted[above][2]);
      }
      key[static_cast<size_t>(y) * k_cols + j] = best;
    }
    begin = end;
  }

  std::vector<size_t> v(k_cols);
  std::vector<Rational> z(k_cols + 1);
  auto offset = [&](const int64_t* c, size_t j) {
    const int64_t q = cols[j];
    return c[j] + kIndexBase * q * q;
  };
  for (int y = 0; y < h; ++y) {
    const int64_t* c = &key[static_cast<size_t>(y) * k_cols];
    size_t k = 0;
    v[0] = 0;
    for (size_t j = 1; j < k_cols; ++j) {
      Rational sj;
      for (;;) {
        sj = {offset(c, j) - offset(c, v[k]), 2 * kIndexBase * (cols[j] - cols[v[k]])};
        // z[0] is -infinity: the first parabola is never removed.
        if (k > 0 && sj.num * z[k].den <= z[k].num * sj.den) {
          --k;
          continue;
        }
        break;
      }
      ++k;
      v[k] = j;
      z[k] = sj;
    }
    const size_t last = k;
    k = 0;
    const size_t row = static_cast<size_t>(y) * w;
    for (int x = 0; x < w; ++x) {
      while (k < last && z[k + 1].num < x * z[k + 1].den) ++k;
      const int64_t dx = x - cols[v[k]];
      const int64_t total = kIndexBase * dx * dx + c[v[k]];
      fn(row + x, static_cast<int32_t>(total % kIndexBase), total / kIndexBase);
    }
  }
}

}  // namespace

NearestMap nearest_exact_edt(const SparsePriorShape& s, std::span<const SparsePoint> points) {
  validate(s, points);
  const size_t n = static_cast<size_t>(s.width) * s.height;
  NearestMap m{std::vector<int32_t>(n), std::vector<int64_t>(n)};
  for_each_nearest(s, points, [&](size_t i, int32_t label, int64_t d2) {
    m.label[i] = label;
    m.dist2_px2[i] = d2;
  });
  return m;
}

void sparse_prior_cpu(const SparsePriorShape& s, std::span<const SparsePoint> points,
                      std::span<float> out) {
  detail::check_out(s, out);
  validate(s, points);
  const size_t n = static_cast<size_t>(s.width) * s.height;
  const float inv = detail::inv_two_sigma2(s);
  // Squared distances are integers: tabulate S2 up to where it underflows to 0 (same expression
  // as the reference, so the values are identical).
  const int64_t underflow = static_cast<int64_t>(std::ceil(104.f / inv)) + 1;
  const int64_t table_size = std::min<int64_t>(underflow, int64_t{1} << 20);
  std::vector<float> s2(static_cast<size_t>(table_size));
  for (int64_t d = 0; d < table_size; ++d) s2[d] = std::exp(-static_cast<float>(d) * inv);
  for_each_nearest(s, points, [&](size_t i, int32_t label, int64_t d2) {
    out[i] = label < 0 ? 0.f : points[static_cast<size_t>(label)].depth_m;
    out[n + i] = d2 < table_size ? s2[d2] : std::exp(-static_cast<float>(d2) * inv);
  });
}

}  // namespace pensight::kernels
