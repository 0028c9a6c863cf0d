#include "kernels/roi_normalize/roi_normalize.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "runtime/cuda_device.h"
#include "runtime/error.h"
#include "runtime/vk_buffer.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::kernels {
namespace {

using testing::VulkanTest;

template <class Pixel>
Image<Pixel> random_image(int w, int h, std::mt19937_64& rng) {
  Image<Pixel> img(w, h);
  std::uniform_int_distribution<int> u(0, (1 << (8 * sizeof(Pixel))) - 1);
  for (Pixel& p : img.pixels) p = static_cast<Pixel>(u(rng));
  return img;
}

// Random origins, always including the four image corners (border reads).
std::vector<RoiOrigin> random_rois(const RoiNormalizeShape& s, int count, std::mt19937_64& rng) {
  const int mx = s.width - s.roi_size, my = s.height - s.roi_size;
  std::vector<RoiOrigin> rois = {{0, 0}, {mx, 0}, {0, my}, {mx, my}};
  std::uniform_int_distribution<int> ux(0, mx), uy(0, my);
  while (static_cast<int>(rois.size()) < count) rois.push_back({ux(rng), uy(rng)});
  return rois;
}

// Runs the Vulkan kernel into a NaN-poisoned output, so any element it fails to write fails.
template <class Pixel>
std::vector<float> run_vulkan(const vk::Context& ctx, const RoiNormalizeVk& kernel,
                              const Image<Pixel>& image, std::span<const RoiOrigin> rois) {
  vk::Buffer image_buf(ctx, kernel.image_bytes());
  image_buf.upload(image.pixels.data(), image.pixels.size() * sizeof(Pixel));
  vk::Buffer roi_buf(ctx, rois.size_bytes());
  roi_buf.upload(rois.data(), rois.size_bytes());
  const size_t n = rois.size() * kernel.shape().roi_size * kernel.shape().roi_size;
  vk::TypedBuffer<float> out(ctx, n);
  out.fill(testing::kPoison);
  vk::CommandStream stream(ctx);
  kernel.record(stream, image_buf, roi_buf, out.raw(), static_cast<uint32_t>(rois.size()));
  stream.submit_and_wait();
  return out.to_vector();
}

void expect_close(const std::vector<float>& got, const std::vector<float>& want, float tol) {
  ASSERT_EQ(got.size(), want.size());
  size_t bad = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    if (!(std::abs(got[i] - want[i]) <= tol)) {  // NaN fails too
      if (++bad <= 5)
        ADD_FAILURE() << "element " << i << ": got " << got[i] << ", want " << want[i];
    }
  }
  EXPECT_EQ(bad, 0u);
}

TEST(RoiNormalizeCpu, OutputHasZeroMeanUnitVariance) {
  std::mt19937_64 rng(testing::fresh_seed());
  const auto img = random_image<uint8_t>(64, 48, rng);
  const std::vector<RoiOrigin> rois = {{3, 5}, {30, 10}};
  std::vector<float> out(2 * 32 * 32, testing::kPoison);
  roi_normalize_cpu(img, rois, 32, out);
  for (int r = 0; r < 2; ++r) {
    double s = 0, q = 0;
    for (int i = 0; i < 1024; ++i)
      s += out[r * 1024 + i], q += out[r * 1024 + i] * out[r * 1024 + i];
    EXPECT_NEAR(s / 1024, 0.0, 1e-5);
    EXPECT_NEAR(q / 1024, 1.0, 1e-4);
  }
  // Pixel (3+2, 5+1) of ROI 0 maps to element 1*32+2.
  double mean = 0, var = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) mean += img.at(3 + x, 5 + y);
  mean /= 1024;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) var += std::pow(img.at(3 + x, 5 + y) - mean, 2);
  var /= 1024;
  EXPECT_NEAR(out[32 + 2], (img.at(5, 6) - mean) / std::sqrt(var), 1e-5);
}

TEST(RoiNormalizeCpu, RejectsRoisOutsideTheImage) {
  ImageU8 img(100, 80);
  std::vector<float> out(16 * 16);
  EXPECT_THROW(roi_normalize_cpu(img, std::vector<RoiOrigin>{{85, 0}}, 16, out), Error);
  EXPECT_THROW(roi_normalize_cpu(img, std::vector<RoiOrigin>{{0, -1}}, 16, out), Error);
  EXPECT_THROW(roi_normalize_cpu(img, std::vector<RoiOrigin>{{0, 0}}, 81, out), Error);
  std::vector<float> small(10);
  EXPECT_THROW(roi_normalize_cpu(img, std::vector<RoiOrigin>{{0, 0}}, 16, small), Error);
}

TEST_F(VulkanTest, RoiNormalizeMatchesCpuOn8Bit) {
  std::mt19937_64 rng(testing::fresh_seed());
  const RoiNormalizeShape shape{720, 540, 8, 300};
  const auto img = random_image<uint8_t>(shape.width, shape.height, rng);
  const auto rois = random_rois(shape, 30, rng);
  RoiNormalizeVk kernel(ctx(), shape);
  std::vector<float> want(rois.size() * 300 * 300);
  roi_normalize_cpu(img, rois, 300, want);
  expect_close(run_vulkan(ctx(), kernel, img, rois), want, 2e-4f);
}

TEST_F(VulkanTest, RoiNormalizeMatchesCpuOn16BitOddSizes) {
  std::mt19937_64 rng(testing::fresh_seed());
  const RoiNormalizeShape shape{333, 201, 16, 77};  // odd width: pixels straddle words
  const auto img = random_image<uint16_t>(shape.width, shape.height, rng);
  const auto rois = random_rois(shape, 9, rng);
  RoiNormalizeVk kernel(ctx(), shape);
  std::vector<float> want(rois.size() * 77 * 77);
  roi_normalize_cpu(img, rois, 77, want);
  expect_close(run_vulkan(ctx(), kernel, img, rois), want, 2e-4f);
}

TEST_F(VulkanTest, RoiNormalizeFlatRoiIsZero) {
  const RoiNormalizeShape shape{64, 64, 16, 32};
  ImageU16 img(64, 64, 65535);
  img.at(40, 40) = 0;  // only the second ROI has contrast
  const std::vector<RoiOrigin> rois = {{0, 0}, {32, 32}};
  RoiNormalizeVk kernel(ctx(), shape);
  const auto got = run_vulkan(ctx(), kernel, img, std::span<const RoiOrigin>(rois));
  std::vector<float> want(2 * 32 * 32);
  roi_normalize_cpu(img, rois, 32, want);
  for (int i = 0; i < 1024; ++i) ASSERT_EQ(got[i], 0.f) << i;
  expect_close(got, want, 2e-4f);
}

TEST_F(VulkanTest, RoiNormalizeRunChecksTheImageShape) {
  RoiNormalizeVk kernel(ctx(), {64, 64, 8, 32});
  EXPECT_THROW(kernel.run(ImageU8(65, 64), std::vector<RoiOrigin>{{0, 0}}), Error);
  EXPECT_THROW(kernel.run(ImageU16(64, 64), std::vector<RoiOrigin>{{0, 0}}), Error);
  EXPECT_THROW(kernel.run(ImageU8(64, 64), std::vector<RoiOrigin>{{40, 0}}), Error);
  EXPECT_THROW(RoiNormalizeVk(ctx(), {64, 64, 12, 32}), Error);
}

TEST(RoiNormalizeCuda, MatchesCpu) {
#if PENSIGHT_HAS_CUDA
  if (!cuda::available()) GTEST_SKIP() << "no CUDA device";
  std::mt19937_64 rng(testing::fresh_seed());
  const RoiNormalizeShape shape{720, 540, 8, 300};
  const auto img = random_image<uint8_t>(shape.width, shape.height, rng);
  const auto rois = random_rois(shape, 30, rng);
  std::vector<float> want(rois.size() * 300 * 300);
  roi_normalize_cpu(img, rois, 300, want);
  expect_close(roi_normalize_cuda(img, rois, 300), want, 2e-4f);
#else
  GTEST_SKIP() << "built without CUDA";
#endif
}

}  // namespace
}  // namespace pensight::kernels
