#include <gtest/gtest.h>

#include "runtime/timing.h"

namespace pensight {
namespace {

TEST(StageTimes, AccumulatesInFirstSeenOrder) {
  StageTimes t;
  t.add("fft", 2.0);
  t.add("pose", 1.0);
  t.add("fft", 4.0);
  ASSERT_EQ(t.stages().size(), 2u);
  EXPECT_EQ(t.stages()[0].name, "fft");
  EXPECT_DOUBLE_EQ(t.stages()[0].total_ms, 6.0);
  EXPECT_EQ(t.stages()[0].count, 2);
  EXPECT_NE(t.summary().find("pose"), std::string::npos);
}

}  // namespace
}  // namespace pensight
