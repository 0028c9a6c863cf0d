// Proves that the validation messenger would catch real mistakes: each test makes one on purpose
// in a context of its own and checks that it was reported. (The shared test context turns such
// reports into failures; here they are the expected outcome.)
#include <gtest/gtest.h>

#include <mutex>
#include <string>
#include <vector>

#include "runtime/vk_buffer.h"
#include "runtime/vk_pipeline.h"
#include "runtime/vk_stream.h"
#include "tests/runtime/axpy_push.h"
#include "tests/runtime/test_shader.h"

namespace pensight {
namespace {

using testing::AxpyPush;

struct Recorder {
  std::mutex mutex;
  std::vector<std::string> messages;
  vk::ContextOptions options() {
    vk::ContextOptions o;
    o.validation = true;
    o.sync_validation = true;
    o.cache_dir = "-";
    o.on_validation_error = [this](const std::string& m) {
      std::lock_guard lock(mutex);
      messages.push_back(m);
    };
    return o;
  }
  bool saw(const std::string& needle) {
    std::lock_guard lock(mutex);
    for (const auto& m : messages) {
      if (m.find(needle) != std::string::npos) return true;
    }
    return false;
  }
};

TEST(Validation, WrongDescriptorLayoutIsReported) {
  Recorder rec;
  {
    vk::Context ctx(rec.options());
    // axpy reads bindings 0 and 1; a layout with only binding 0 is invalid.
    vk::Pipeline wrong(ctx, {.shader = testing::test_shader("runtime_test/axpy"),
                             .num_buffers = 1,
                             .push_constant_bytes = sizeof(AxpyPush)});
    EXPECT_GT(ctx.validation_errors(), 0u);
  }
  EXPECT_FALSE(rec.messages.empty());
}

TEST(Validation, MissingBarrierIsReported) {
  Recorder rec;
  {
    vk::Context ctx(rec.options());
    const uint32_t n = 256;
    vk::TypedBuffer<float> x(ctx, n), y(ctx, n), z(ctx, n);
    x.fill(1.f);
    y.fill(0.f);
    z.fill(0.f);
    vk::Pipeline axpy(ctx, {.shader = testing::test_shader("runtime_test/axpy"),
                            .num_buffers = 2,
                            .push_constant_bytes = sizeof(AxpyPush)});
    vk::CommandStream stream(ctx);
    // y is written but declared read-only, so the stream inserts no barrier before y is read.
    stream.dispatch(axpy, {vk::in(x), vk::in(y)}, {4}, AxpyPush{1.f, n});
    stream.dispatch(axpy, {vk::in(y), vk::inout(z)}, {4}, AxpyPush{1.f, n});
    EXPECT_EQ(stream.num_barriers(), 0u);
    stream.submit_and_wait();
    EXPECT_GT(ctx.validation_errors(), 0u);
  }
  EXPECT_TRUE(rec.saw("SYNC-HAZARD")) << (rec.messages.empty() ? "no messages" : rec.messages[0]);
}

TEST(Validation, CorrectChainIsClean) {
  Recorder rec;
  vk::Context ctx(rec.options());
  const uint32_t n = 256;
  vk::TypedBuffer<float> x(ctx, n), y(ctx, n), z(ctx, n);
  x.fill(1.f);
  y.fill(0.f);
  z.fill(0.f);
  vk::Pipeline axpy(ctx, {.shader = testing::test_shader("runtime_test/axpy"),
                          .num_buffers = 2,
                          .push_constant_bytes = sizeof(AxpyPush)});
  vk::CommandStream stream(ctx);
  stream.dispatch(axpy, {vk::in(x), vk::inout(y)}, {4}, AxpyPush{1.f, n});
  stream.dispatch(axpy, {vk::in(y), vk::inout(z)}, {4}, AxpyPush{1.f, n});
  stream.submit_and_wait();
  EXPECT_EQ(ctx.validation_errors(), 0u) << rec.messages.front();
}

}  // namespace
}  // namespace pensight
