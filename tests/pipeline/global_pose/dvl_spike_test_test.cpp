// DvlSpikeTest: spikes of one and two samples in any axis are rejected and counted, a sustained
// change of velocity (a manoeuvre beyond the bound) is released in order, a spike followed by a
// dropout expires, and steady noisy samples pass. Fresh random noise and spike sizes each run.
// MotionSchedule (motion_schedule.h), which shares the spike test's bound: quiet spans only after
// the samples stayed within it for settle_s, manoeuvres and overdue samples are not quiet, and a
// span predicted with the other noise asks for a re-apply from its start.
#include <gtest/gtest.h>

#include <random>

#include "pipeline/global_pose/dvl_spike_test.h"
#include "pipeline/global_pose/motion_schedule.h"
#include "tests/support/vulkan_fixture.h"

namespace pensight::global_pose {
namespace {

constexpr int64_t kStep = 250'000'000;  // 4 Hz

DvlSample sample(int k) {
  DvlSample s;
  s.timestamp_ns = k * kStep;
  s.valid = true;
  return s;
}

TEST(DvlSpikeTest, OneAndTwoSampleSpikesInAnyAxisAreRejectedAndSteadyNoisePasses) {
  std::mt19937_64 rng(testing::fresh_seed());
  std::normal_distribution<double> noise(0, 0.005);
  std::uniform_real_distribution<double> size(0.3, 1.0), sign(-1, 1);
  DvlSpikeTest test;
  std::vector<int64_t> released;
  int expected_spikes = 0;
  for (int k = 0; k < 400; ++k) {
    // Following at 0.2 m/s with a slow acceleration of 0.05 m/s^2 amplitude.
    Eigen::Vector3d v(0.02 * std::sin(0.1 * k), 0.2 + 0.05 * std::cos(0.05 * k), 0.0);
    v += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    const bool spike = k % 40 == 20 || k % 40 == 21;
    const bool two = (k / 40) % 2 == 1;
    if (spike && (k % 40 == 20 || two)) {
      Eigen::Vector3d dir = Eigen::Vector3d::Zero();
      dir((k / 40) % 3) = sign(rng) < 0 ? -1 : 1;
      v += size(rng) * dir;
      ++expected_spikes;
    }
    for (const DvlSample& r : test.push(sample(k), v)) released.push_back(r.timestamp_ns);
  }
  EXPECT_EQ(test.spikes(), expected_spikes);
  EXPECT_EQ(static_cast<int>(released.size()), 400 - expected_spikes);
  EXPECT_TRUE(std::is_sorted(released.begin(), released.end()));
}

TEST(DvlSpikeTest, ASustainedChangeIsAManoeuvreAndIsReleasedInOrder) {
  DvlSpikeTest test;
  for (int k = 0; k < 4; ++k)
    EXPECT_EQ(test.push(sample(k), Eigen::Vector3d(0, 0.2, 0)).size(), 1u);
  // 0.8 m/s more for good: held for max_spike_samples, then all released.
  EXPECT_TRUE(test.push(sample(4), Eigen::Vector3d(0.8, 0.2, 0)).empty());
  EXPECT_TRUE(test.push(sample(5), Eigen::Vector3d(0.8, 0.2, 0)).empty());
  const auto out = test.push(sample(6), Eigen::Vector3d(0.8, 0.2, 0));
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].timestamp_ns, 4 * kStep);
  EXPECT_EQ(out[2].timestamp_ns, 6 * kStep);
  EXPECT_EQ(test.spikes(), 0);
  EXPECT_EQ(test.push(sample(7), Eigen::Vector3d(0.8, 0.2, 0)).size(), 1u);
}

TEST(DvlSpikeTest, ASpikeFollowedByADropoutExpires) {
  DvlSpikeTest test;
  EXPECT_EQ(test.push(sample(0), Eigen::Vector3d(0, 0.2, 0)).size(), 1u);
  EXPECT_TRUE(test.push(sample(1), Eigen::Vector3d(0, 0.2, 0.5)).empty());
  test.expire(sample(1).timestamp_ns + 900'000'000);
  EXPECT_EQ(test.spikes(), 0);
  test.expire(sample(1).timestamp_ns + 1'100'000'000);
  EXPECT_EQ(test.spikes(), 1);
}

TEST(MotionSchedule, QuietAfterSettlingManoeuvresAndOverdueSamplesAreNot) {
  MotionSchedule schedule;  // settle_s 1 s
  const Eigen::Vector3d along(0, 0.2, 0);
  EXPECT_FALSE(schedule.add(0, along));
  EXPECT_FALSE(schedule.quiet(0, kStep / 2));  // one sample vouches for nothing
  for (int k = 1; k <= 3; ++k) EXPECT_FALSE(schedule.add(k * kStep, along));
  EXPECT_FALSE(schedule.quiet(2 * kStep, 3 * kStep));  // 0.75 s within the bound: settling
  // The first quiet span follows manoeuvring ones: predicted with the manoeuvring noise, it is
  // applied again from its start.
  EXPECT_EQ(schedule.add(4 * kStep, along), std::optional<int64_t>(3 * kStep));
  EXPECT_TRUE(schedule.quiet(3 * kStep, 4 * kStep));
  EXPECT_TRUE(schedule.quiet(4 * kStep, 4 * kStep + kStep / 2));   // the next sample is not due
  EXPECT_FALSE(schedule.quiet(4 * kStep, 4 * kStep + kStep * 2));  // overdue: maybe held
  EXPECT_FALSE(schedule.add(5 * kStep, along));
  // 0.3 m/s more in 0.25 s (1.2 m/s^2): a manoeuvre, in a span predicted as quiet.
  EXPECT_EQ(schedule.add(6 * kStep, Eigen::Vector3d(0.3, 0.2, 0)),
            std::optional<int64_t>(5 * kStep));
  EXPECT_FALSE(schedule.quiet(5 * kStep, 6 * kStep));
  EXPECT_FALSE(schedule.quiet(6 * kStep, 6 * kStep + kStep / 2));
  // Steady again: settling restarts.
  EXPECT_FALSE(schedule.add(7 * kStep, Eigen::Vector3d(0.3, 0.2, 0)));
  EXPECT_FALSE(schedule.quiet(6 * kStep, 7 * kStep));
}

}  // namespace
}  // namespace pensight::global_pose
