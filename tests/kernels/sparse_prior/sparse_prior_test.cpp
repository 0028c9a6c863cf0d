#include "kernels/sparse_prior/sparse_prior.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "core/error.h"
#include "runtime/vk_buffer.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::kernels {
namespace {

using testing::VulkanTest;

// Random points with distinct depths, plus the four corners, points on every border and exact
// duplicates (same pixel, different index), which make ties.
std::vector<SparsePoint> random_points(const SparsePriorShape& s, int count, std::mt19937_64& rng) {
  std::uniform_real_distribution<float> ux(-0.49f, static_cast<float>(s.width) - 0.51f);
  std::uniform_real_distribution<float> uy(-0.49f, static_cast<float>(s.height) - 0.51f);
  const float w1 = static_cast<float>(s.width - 1), h1 = static_cast<float>(s.height - 1);
  std::vector<SparsePoint> p = {{0, 0, 0},        {w1, 0, 0},      {0, h1, 0},
                                {w1, h1, 0},      {ux(rng), 0, 0}, {0, uy(rng), 0},
                                {w1, uy(rng), 0}, {ux(rng), h1, 0}};
  while (static_cast<int>(p.size()) < count) {
    if (p.size() % 7 == 0) {
      p.push_back(p[rng() % p.size()]);  // duplicate
    } else {
      p.push_back({ux(rng), uy(rng), 0});
    }
  }
  p.resize(static_cast<size_t>(count));
  for (size_t i = 0; i < p.size(); ++i) p[i].depth_m = 1.f + 0.01f * static_cast<float>(i);
  return p;
}

void expect_same_map(const NearestMap& got, const NearestMap& want) {
  ASSERT_EQ(got.label.size(), want.label.size());
  size_t bad = 0;
  for (size_t i = 0; i < got.label.size(); ++i) {
    if (got.label[i] != want.label[i] || got.dist2_px2[i] != want.dist2_px2[i]) {
      if (++bad <= 5) {
        ADD_FAILURE() << "pixel " << i << ": label " << got.label[i] << " d2 " << got.dist2_px2[i]
                      << ", want label " << want.label[i] << " d2 " << want.dist2_px2[i];
      }
    }
  }
  EXPECT_EQ(bad, 0u);
}

// S1 must be bit-equal (depths are distinct, so it identifies the chosen point); S2 within
// `s2_tol` absolute (device exp() is allowed a few ulp).
void expect_prior(const std::vector<float>& got, const std::vector<float>& want, size_t offset,
                  float s2_tol) {
  size_t bad = 0;
  const size_t plane = want.size() / 2;
  for (size_t i = 0; i < want.size(); ++i) {
    const float g = got[offset + i], w = want[i];
    const bool ok = i < plane ? g == w : std::abs(g - w) <= s2_tol;  // NaN fails both
    if (!ok && ++bad <= 5) ADD_FAILURE() << "element " << i << ": got " << g << ", want " << w;
  }
  EXPECT_EQ(bad, 0u);
}

TEST(SparsePriorCpu, ExactEdtMatchesBruteForce) {
  std::mt19937_64 rng(testing::fresh_seed());
  for (const auto& [w, h, n] : std::vector<std::array<int, 3>>{
           {320, 240, 30}, {97, 61, 300}, {64, 64, 1}, {33, 190, 1024}, {1, 50, 5}, {50, 1, 5}}) {
    const SparsePriorShape s{w, h, 10};
    const auto pts = random_points(s, std::max(n, 8), rng);
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    expect_same_map(nearest_exact_edt(s, pts), nearest_brute_force(s, pts));
  }
}

TEST(SparsePriorCpu, TiesOnALatticeGoToTheLowestIndex) {
  // Points on a 6 px lattice, listed in a shuffled order: every cell centre is a 4-way tie.
  std::mt19937_64 rng(testing::fresh_seed());
  const SparsePriorShape s{60, 48, 10};
  std::vector<SparsePoint> pts;
  for (int y = 0; y < 48; y += 6)
    for (int x = 0; x < 60; x += 6) pts.push_back({float(x), float(y), float(pts.size())});
  std::shuffle(pts.begin(), pts.end(), rng);
  const auto brute = nearest_brute_force(s, pts);
  expect_same_map(nearest_exact_edt(s, pts), brute);
  // Pixel (3, 3) is equidistant from (0,0), (6,0), (0,6), (6,6): the lowest index must win.
  int lowest = 1 << 30;
  for (int i = 0; i < static_cast<int>(pts.size()); ++i) {
    if (std::abs(pts[i].x_px - 3) == 3 && std::abs(pts[i].y_px - 3) == 3)
      lowest = std::min(lowest, i);
  }
  EXPECT_EQ(brute.label[3 * 60 + 3], lowest);
}

TEST(SparsePriorCpu, FastPathEqualsReferenceAndFormula) {
  std::mt19937_64 rng(testing::fresh_seed());
  const SparsePriorShape s{123, 77, 7.5f};
  const auto pts = random_points(s, 40, rng);
  const size_t n = 123 * 77;
  std::vector<float> ref(2 * n, testing::kPoison), fast(2 * n, testing::kPoison);
  sparse_prior_cpu_reference(s, pts, ref);
  sparse_prior_cpu(s, pts, fast);
  for (size_t i = 0; i < 2 * n; ++i) ASSERT_EQ(fast[i], ref[i]) << i;
  // Pixel (5, 9): S1 and S2 from its true nearest point.
  double best = 1e30;
  float depth = 0;
  for (const auto& p : pts) {
    const double d2 =
        std::pow(5 - std::floor(p.x_px + 0.5), 2) + std::pow(9 - std::floor(p.y_px + 0.5), 2);
    if (d2 < best) best = d2, depth = p.depth_m;
  }
  EXPECT_EQ(ref[9 * 123 + 5], depth);
  EXPECT_NEAR(ref[n + 9 * 123 + 5], std::exp(-best / (2 * 7.5 * 7.5)), 1e-6);
}

TEST(SparsePriorCpu, NoPointsGiveZeroDepthAndDiagonalDistance) {
  const SparsePriorShape s{40, 30, 10};
  std::vector<float> out(2 * 1200, testing::kPoison);
  sparse_prior_cpu(s, {}, out);
  for (size_t i = 0; i < 1200; ++i) {
    ASSERT_EQ(out[i], 0.f);
    ASSERT_FLOAT_EQ(out[1200 + i], std::exp(-2500.f / 200.f));
  }
}

TEST(SparsePriorCpu, RejectsBadInput) {
  const SparsePriorShape s{40, 30, 10};
  std::vector<float> out(2 * 1200);
  const auto nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(sparse_prior_cpu(s, std::vector<SparsePoint>{{40.f, 0, 1}}, out), Error);
  EXPECT_THROW(sparse_prior_cpu(s, std::vector<SparsePoint>{{-0.6f, 0, 1}}, out), Error);
  EXPECT_THROW(sparse_prior_cpu(s, std::vector<SparsePoint>{{1, nan, 1}}, out), Error);
  EXPECT_THROW(sparse_prior_cpu(s, std::vector<SparsePoint>{{1, 1, nan}}, out), Error);
  EXPECT_THROW(sparse_prior_cpu(s, std::vector<SparsePoint>(1025), out), Error);
  std::vector<float> small(100);
  EXPECT_THROW(sparse_prior_cpu(s, {}, small), Error);
  EXPECT_THROW(sparse_prior_cpu({0, 30, 10}, {}, out), Error);
  EXPECT_THROW(sparse_prior_cpu({40, 30, 0}, {}, out), Error);
}

// OpenCV's distanceTransform with DIST_LABEL_PIXEL propagates labels with a 5x5 mask: some
// pixels get a seed that is not their nearest. Ours never does.
TEST(SparsePriorCpu, OpenCvLabelsAreApproximateOursAreExact) {
  std::mt19937_64 rng(testing::fresh_seed());
  const SparsePriorShape s{720, 540, 10};
  const auto pts = random_points(s, 300, rng);
  const auto exact = nearest_brute_force(s, pts);
  cv::Mat seeds(s.height, s.width, CV_8U, cv::Scalar(1));
  for (const auto& p : pts)
    seeds.at<uint8_t>(int(std::floor(p.y_px + 0.5)), int(std::floor(p.x_px + 0.5))) = 0;
  cv::Mat dist, labels;
  cv::distanceTransform(seeds, dist, labels, cv::DIST_L2, cv::DIST_MASK_5, cv::DIST_LABEL_PIXEL);
  std::vector<cv::Point> seed_of_label(static_cast<size_t>(s.width) * s.height + 1);
  for (const auto& p : pts) {
    const cv::Point q(int(std::floor(p.x_px + 0.5)), int(std::floor(p.y_px + 0.5)));
    seed_of_label[static_cast<size_t>(labels.at<int>(q))] = q;
  }
  size_t opencv_wrong = 0;
  for (int y = 0; y < s.height; ++y) {
    for (int x = 0; x < s.width; ++x) {
      const cv::Point q = seed_of_label[static_cast<size_t>(labels.at<int>(y, x))];
      const int64_t d2 = int64_t(x - q.x) * (x - q.x) + int64_t(y - q.y) * (y - q.y);
      if (d2 != exact.dist2_px2[static_cast<size_t>(y) * s.width + x]) ++opencv_wrong;
    }
  }
  std::printf("cv::distanceTransform labels: %zu of %d pixels (%.2f%%) not at their nearest seed\n",
              opencv_wrong, s.width * s.height,
              100.0 * double(opencv_wrong) / (s.width * s.height));
  EXPECT_GT(opencv_wrong, 0u);
  expect_same_map(nearest_exact_edt(s, pts), exact);
}

std::vector<float> run_vulkan(const vk::Context& ctx, const SparsePriorVk& kernel,
                              std::span<const SparsePoint> pts, uint32_t offset, size_t total) {
  vk::Buffer point_buf(ctx, std::max<size_t>(pts.size_bytes(), 16));
  if (!pts.empty()) point_buf.upload(pts.data(), pts.size_bytes());
  vk::TypedBuffer<SparsePriorParams> params(ctx, 1);
  params.fill({static_cast<uint32_t>(pts.size())});
  vk::TypedBuffer<float> out(ctx, total);
  out.fill(testing::kPoison);
  vk::CommandStream stream(ctx);
  kernel.record(stream, point_buf, params, out.raw(), offset);
  stream.submit_and_wait();
  return out.to_vector();
}

TEST_F(VulkanTest, SparsePriorMatchesReference) {
  std::mt19937_64 rng(testing::fresh_seed());
  for (const auto& [w, h, n] : std::vector<std::array<int, 3>>{
           {320, 240, 30}, {333, 201, 300}, {720, 540, 1024}, {17, 5, 8}}) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " " + std::to_string(n));
    const SparsePriorShape s{w, h, 10};
    const auto pts = random_points(s, n, rng);
    const size_t plane = static_cast<size_t>(w) * h;
    std::vector<float> want(2 * plane);
    sparse_prior_cpu_reference(s, pts, want);
    const SparsePriorVk kernel(ctx(), s);
    // Channels 1 and 2 of a 4-channel NCHW tensor: the other channels stay untouched.
    const auto got = run_vulkan(ctx(), kernel, pts, static_cast<uint32_t>(plane), 4 * plane);
    expect_prior(got, want, plane, 1e-6f);
    for (size_t i = 0; i < plane; ++i) {
      ASSERT_TRUE(std::isnan(got[i]) && std::isnan(got[3 * plane + i])) << i;
    }
  }
}

TEST_F(VulkanTest, SparsePriorWithoutPoints) {
  const SparsePriorShape s{40, 30, 10};
  std::vector<float> want(2 * 1200);
  sparse_prior_cpu_reference(s, {}, want);
  expect_prior(run_vulkan(ctx(), SparsePriorVk(ctx(), s), {}, 0, 2400), want, 0, 1e-6f);
  EXPECT_THROW(SparsePriorVk(ctx(), s).run(std::vector<SparsePoint>{{-3, 0, 1}}), Error);
}

// One stream recorded once serves frames with different point counts: the count lives in the
// parameter buffer, read when the stream runs. Outputs are poisoned before each frame.
TEST_F(VulkanTest, SparsePriorStreamRecordedOnceFollowsThePointCount) {
  std::mt19937_64 rng(testing::fresh_seed());
  const SparsePriorShape s{96, 70, 8};
  const size_t plane = static_cast<size_t>(s.width) * s.height;
  const SparsePriorVk kernel(ctx(), s);
  vk::Buffer point_buf(ctx(), 64 * sizeof(SparsePoint));
  vk::TypedBuffer<SparsePriorParams> params(ctx(), 1);
  vk::TypedBuffer<float> out(ctx(), 3 * plane);
  vk::CommandStream stream(ctx());
  kernel.record(stream, point_buf, params, out.raw(), static_cast<uint32_t>(plane));
  for (const int n : {30, 7, 0, 64}) {
    SCOPED_TRACE(std::to_string(n) + " points");
    const auto pts = random_points(s, n, rng);
    std::vector<float> want(2 * plane);
    sparse_prior_cpu_reference(s, pts, want);
    if (n > 0) point_buf.upload(pts.data(), pts.size() * sizeof(SparsePoint));
    params.fill({static_cast<uint32_t>(n)});
    out.fill(testing::kPoison);
    stream.submit_and_wait();
    const auto got = out.to_vector();
    expect_prior(got, want, plane, 1e-6f);
    for (size_t i = 0; i < plane; ++i) ASSERT_TRUE(std::isnan(got[i])) << i;
  }
  EXPECT_EQ(stream.num_commands(), 1u);
}

// A count larger than the points buffer holds (a stale count, a buffer shrunk) reads only the
// points the buffer has, never past its end.
TEST_F(VulkanTest, SparsePriorCountIsClampedToThePointsBuffer) {
  std::mt19937_64 rng(testing::fresh_seed());
  const SparsePriorShape s{50, 40, 10};
  const auto pts = random_points(s, 20, rng);
  std::vector<float> want(2 * 2000);
  sparse_prior_cpu_reference(s, pts, want);
  const SparsePriorVk kernel(ctx(), s);
  vk::Buffer point_buf(ctx(), pts.size() * sizeof(SparsePoint));
  point_buf.upload(pts.data(), pts.size() * sizeof(SparsePoint));
  vk::TypedBuffer<SparsePriorParams> params(ctx(), 1);
  params.fill({500});
  vk::TypedBuffer<float> out(ctx(), 2 * 2000);
  out.fill(testing::kPoison);
  vk::CommandStream stream(ctx());
  kernel.record(stream, point_buf, params, out.raw());
  stream.submit_and_wait();
  expect_prior(out.to_vector(), want, 0, 1e-6f);
  EXPECT_THROW(kernel.record(stream, point_buf, params, out.raw(), 1), Error);  // output too small
}

}  // namespace
}  // namespace pensight::kernels
