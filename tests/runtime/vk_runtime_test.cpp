#include <gtest/gtest.h>

#include <bit>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>
#include <thread>

#include "core/error.h"
#include "runtime/vk_buffer.h"
#include "runtime/vk_pipeline.h"
#include "runtime/vk_stream.h"
#include "tests/runtime/axpy_push.h"
#include "tests/runtime/test_shader.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight {
namespace {

using testing::AxpyPush;
using testing::VulkanTest;

vk::Pipeline make_axpy(const vk::Context& ctx) {
  return vk::Pipeline(ctx, {.shader = testing::test_shader("runtime_test/axpy"),
                            .num_buffers = 2,
                            .push_constant_bytes = sizeof(AxpyPush)});
}

vk::PipelineDesc axpy_desc(float scale) {
  return {.shader = testing::test_shader("runtime_test/axpy"),
          .num_buffers = 2,
          .push_constant_bytes = sizeof(AxpyPush),
          .specialization = {std::bit_cast<uint32_t>(scale)}};
}

vk::Groups groups_for(uint32_t n) {
  return {(n + 63) / 64, 1, 1};
}

std::vector<float> random_floats(size_t n, std::mt19937_64& rng) {
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<float> v(n);
  for (float& x : v) x = u(rng);
  return v;
}

TEST_F(VulkanTest, DeviceIsDescribed) {
  const vk::DeviceInfo& info = ctx().info();
  EXPECT_FALSE(info.name.empty());
  EXPECT_FALSE(info.driver.empty());
  EXPECT_GE(info.max_workgroup_invocations, 256u);
  const auto all = vk::Context::list_devices();
  ASSERT_GT(all.size(), info.index);
  EXPECT_EQ(all[info.index].name, info.name);
}

TEST_F(VulkanTest, BufferRoundTripAndRangeCheck) {
  std::mt19937_64 rng(testing::fresh_seed());
  const auto data = random_floats(1000, rng);
  for (auto usage : {vk::MemoryUsage::kDevice, vk::MemoryUsage::kReadback}) {
    vk::TypedBuffer<float> buf(ctx(), data.size(), usage);
    buf.fill(testing::kPoison);
    buf.upload(data);
    EXPECT_EQ(buf.to_vector(), data);
    std::vector<float> tail(10);
    buf.download(tail, 990);
    EXPECT_EQ(tail, std::vector<float>(data.end() - 10, data.end()));
    EXPECT_THROW(buf.download(tail, 995), Error);
    EXPECT_THROW(buf.upload(tail, 991), Error);
  }
}

TEST_F(VulkanTest, UnknownShaderIsNamed) {
  try {
    testing::test_shader("no/such_shader");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no/such_shader"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("runtime_test"), std::string::npos) << e.what();
  }
  // The kernels' and the renderer's shaders are not the test's: each layer embeds its own.
  EXPECT_THROW(testing::test_shader("fft_roi/extract"), Error);
}

TEST_F(VulkanTest, CodeThatIsNotSpirvIsRefusedBeforeTheDriver) {
  const uint32_t not_spirv[8] = {};
  try {
    vk::Pipeline p(ctx(), {.shader = {"bad/words", not_spirv}});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad/words"), std::string::npos) << e.what();
  }
}

TEST_F(VulkanTest, DependentChainGetsOneBarrierAndIsCorrect) {
  std::mt19937_64 rng(testing::fresh_seed());
  const uint32_t n = 1000;
  const auto x = random_floats(n, rng), y0 = random_floats(n, rng), z0 = random_floats(n, rng);
  vk::TypedBuffer<float> bx(ctx(), n), by(ctx(), n), bz(ctx(), n);
  bx.upload(x);
  by.upload(y0);
  bz.upload(z0);
  const vk::Pipeline axpy = make_axpy(ctx());

  vk::CommandStream stream(ctx());
  stream.dispatch(axpy, {vk::in(bx), vk::inout(by)}, groups_for(n), AxpyPush{2.f, n}, "y+=2x");
  stream.dispatch(axpy, {vk::in(by), vk::inout(bz)}, groups_for(n), AxpyPush{3.f, n}, "z+=3y");
  EXPECT_EQ(stream.num_barriers(), 1u);  // read-after-write on y
  stream.submit_and_wait();
  const auto y = by.to_vector(), z = bz.to_vector();
  for (uint32_t i = 0; i < n; ++i) {
    ASSERT_FLOAT_EQ(y[i], 2 * x[i] + y0[i]) << i;
    ASSERT_NEAR(z[i], 3 * y[i] + z0[i], 1e-5f) << i;
  }

  // Submitting again re-runs the recorded chain on the current contents.
  stream.submit_and_wait();
  const auto y2 = by.to_vector();
  for (uint32_t i = 0; i < n; ++i) ASSERT_NEAR(y2[i], 2 * x[i] + y[i], 1e-5f) << i;

  const auto t = stream.timings();
  if (ctx().info().timestamps) {
    ASSERT_EQ(t.size(), 2u);
    EXPECT_EQ(t[0].name, "y+=2x");
    EXPECT_EQ(t[1].name, "z+=3y");
    for (const auto& d : t) EXPECT_GE(d.device_ms, 0.0);
  }
}

TEST_F(VulkanTest, IndependentDispatchesNeedNoBarrier) {
  const uint32_t n = 256;
  vk::TypedBuffer<float> bx(ctx(), n), by(ctx(), n), bz(ctx(), n);
  bx.fill(1.f);
  by.fill(0.f);
  bz.fill(0.f);
  const vk::Pipeline axpy = make_axpy(ctx());
  vk::CommandStream stream(ctx());
  stream.dispatch(axpy, {vk::in(bx), vk::inout(by)}, groups_for(n), AxpyPush{1.f, n});
  stream.dispatch(axpy, {vk::in(bx), vk::inout(bz)}, groups_for(n), AxpyPush{2.f, n});
  EXPECT_EQ(stream.num_barriers(), 0u);  // both only read x
  // Overwriting x after it was read is a write-after-read hazard.
  stream.dispatch(axpy, {vk::in(by), vk::inout(bx)}, groups_for(n), AxpyPush{1.f, n});
  EXPECT_EQ(stream.num_barriers(), 1u);
  stream.submit_and_wait();
  EXPECT_EQ(by.to_vector(), std::vector<float>(n, 1.f));
  EXPECT_EQ(bz.to_vector(), std::vector<float>(n, 2.f));
  EXPECT_EQ(bx.to_vector(), std::vector<float>(n, 2.f));
}

TEST_F(VulkanTest, CopyIsOrderedWithDispatches) {
  const uint32_t n = 300;
  vk::TypedBuffer<float> bx(ctx(), n), by(ctx(), n), readback(ctx(), n, vk::MemoryUsage::kReadback);
  bx.fill(1.f);
  by.fill(5.f);
  readback.fill(testing::kPoison);
  const vk::Pipeline axpy = make_axpy(ctx());
  vk::CommandStream stream(ctx());
  stream.dispatch(axpy, {vk::in(bx), vk::inout(by)}, groups_for(n), AxpyPush{1.f, n});
  stream.copy(by.raw(), readback.raw());
  stream.submit_and_wait();
  EXPECT_EQ(readback.to_vector(), std::vector<float>(n, 6.f));
  EXPECT_THROW(stream.copy(by.raw(), readback.raw(), 4 * n + 4), Error);
}

TEST_F(VulkanTest, DispatchChecksBindingsAndPushConstants) {
  vk::TypedBuffer<float> b(ctx(), 4);
  const vk::Pipeline axpy = make_axpy(ctx());
  vk::CommandStream stream(ctx());
  EXPECT_THROW(stream.dispatch(axpy, {vk::in(b)}, {1}, AxpyPush{1.f, 4}), Error);
  EXPECT_THROW(stream.dispatch(axpy, {vk::in(b), vk::inout(b)}, {1}, 1.0f), Error);
}

// Scales unlikely to be used by any other test of this binary, so the counts below are this
// test's own.
constexpr float kScaleA = 3.25f, kScaleB = -0.5f;

TEST_F(VulkanTest, ContextBuildsEachPipelineOnce) {
  const size_t before = ctx().num_pipelines();
  const vk::Pipeline& a = ctx().pipeline(axpy_desc(kScaleA));
  EXPECT_EQ(ctx().num_pipelines(), before + 1);
  EXPECT_EQ(&ctx().pipeline(axpy_desc(kScaleA)), &a);  // same description: the same object
  EXPECT_EQ(ctx().num_pipelines(), before + 1);
  const vk::Pipeline& b = ctx().pipeline(axpy_desc(kScaleB));
  EXPECT_NE(&b, &a);  // different specialization: a pipeline of its own
  EXPECT_EQ(ctx().num_pipelines(), before + 2);
  EXPECT_EQ(b.desc(), axpy_desc(kScaleB));

  // Each computes with its own specialization.
  std::mt19937_64 rng(testing::fresh_seed());
  const uint32_t n = 500;
  const auto x = random_floats(n, rng);
  vk::TypedBuffer<float> bx(ctx(), n), ya(ctx(), n), yb(ctx(), n);
  bx.upload(x);
  ya.fill(0.f);
  yb.fill(0.f);
  vk::CommandStream stream(ctx());
  stream.dispatch(a, {vk::in(bx), vk::inout(ya)}, groups_for(n), AxpyPush{2.f, n});
  stream.dispatch(b, {vk::in(bx), vk::inout(yb)}, groups_for(n), AxpyPush{2.f, n});
  stream.submit_and_wait();
  const auto got_a = ya.to_vector(), got_b = yb.to_vector();
  for (uint32_t i = 0; i < n; ++i) {
    ASSERT_FLOAT_EQ(got_a[i], kScaleA * 2.f * x[i]) << i;
    ASSERT_FLOAT_EQ(got_b[i], kScaleB * 2.f * x[i]) << i;
  }
}

TEST_F(VulkanTest, PipelineRequestsFromManyThreadsAgree) {
  // Fresh descriptions (scales no other test uses), requested from all threads at once in
  // different orders: each is built once and every thread gets the same object.
  constexpr int kThreads = 8, kDescs = 6;
  std::vector<vk::PipelineDesc> descs;
  for (int d = 0; d < kDescs; ++d) descs.push_back(axpy_desc(100.f + static_cast<float>(d)));
  const size_t before = ctx().num_pipelines();
  std::vector<std::vector<const vk::Pipeline*>> got(kThreads,
                                                    std::vector<const vk::Pipeline*>(kDescs));
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < kDescs; ++i) {
        const int d = (t % 2 ? kDescs - 1 - i : i + t) % kDescs;
        got[t][d] = &ctx().pipeline(descs[d]);
      }
    });
  }
  for (auto& th : threads) th.join();
  EXPECT_EQ(ctx().num_pipelines(), before + kDescs);
  for (int d = 0; d < kDescs; ++d) {
    EXPECT_EQ(got[0][d]->desc(), descs[d]);
    for (int t = 1; t < kThreads; ++t) EXPECT_EQ(got[t][d], got[0][d]) << t << " " << d;
  }
}

TEST_F(VulkanTest, FailedPipelineIsNamedAndNotKept) {
  const size_t before = ctx().num_pipelines();
  const uint32_t not_spirv[8] = {};
  EXPECT_THROW(ctx().pipeline({.shader = {"bad/words", not_spirv}}), Error);
  EXPECT_THROW(ctx().pipeline({.shader = {"bad/words", not_spirv}}), Error);
  EXPECT_EQ(ctx().num_pipelines(), before);
}

TEST_F(VulkanTest, PipelineCacheIsPersisted) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("pensight-cache-test-" + std::to_string(testing::fresh_seed()));
  std::filesystem::path file;
  {
    vk::Context c({.cache_dir = dir});
    file = c.pipeline_cache_path();
    EXPECT_EQ(file.parent_path(), dir);
    make_axpy(c);
  }
  ASSERT_TRUE(std::filesystem::exists(file));
  // At least the 32-byte VkPipelineCacheHeaderVersionOne (lavapipe stores nothing more).
  EXPECT_GE(std::filesystem::file_size(file), 32u);
  {
    vk::Context c({.cache_dir = dir});  // loads the file written above
    make_axpy(c);
  }
  {
    std::ofstream(file, std::ios::trunc) << "not a pipeline cache";
    vk::Context c({.cache_dir = dir});  // a corrupt file is ignored, then rewritten
    make_axpy(c);
  }
  EXPECT_GE(std::filesystem::file_size(file), 32u);
  std::filesystem::remove_all(dir);
}

TEST_F(VulkanTest, UnknownDeviceListsTheAvailableOnes) {
  try {
    vk::Context c({.device = "no-such-gpu", .cache_dir = "-"});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no-such-gpu"), std::string::npos) << what;
    EXPECT_NE(what.find(ctx().info().name), std::string::npos) << what;
  }
  vk::Context by_index({.device = std::to_string(ctx().info().index), .cache_dir = "-"});
  EXPECT_EQ(by_index.info().name, ctx().info().name);
}

}  // namespace
}  // namespace pensight
