#include "conde_sim/loop_watch.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

using conde_sim::LoopWatch;

TEST(LoopWatch, NoBeatYetIsNotAStall) {
  LoopWatch watch(5.0);
  std::string report;
  EXPECT_FALSE(watch.checkStall(1000.0, &report));  // start-up (world loading) is not watched
}

TEST(LoopWatch, ABeatingLoopIsNeverStuck) {
  LoopWatch watch(5.0);
  for (int i = 0; i < 100; ++i) {
    const double wall_s = 100.0 + i;  // one beat per wall second
    watch.beat("stepping", 0.001 * i, wall_s);
    EXPECT_FALSE(watch.checkStall(wall_s + 0.9, nullptr));
  }
  EXPECT_EQ(watch.stalls(), 0u);
}

TEST(LoopWatch, AStallIsReportedOnceWithItsPhaseAndTime) {
  LoopWatch watch(5.0);
  watch.beat("stepping", 0.010, 100.0);
  watch.beat("waiting for lock-step answers", 0.011, 100.5);
  std::string report;
  EXPECT_FALSE(watch.checkStall(105.4, &report));  // 4.9 s: not yet
  ASSERT_TRUE(watch.checkStall(105.6, &report));
  EXPECT_EQ(report,
            "the step loop has not moved for 5.1 s of wall time, at t = 0.011 s, in: waiting for lock-step answers");
  EXPECT_FALSE(watch.checkStall(200.0, &report));  // the same stall: once
  EXPECT_EQ(watch.stalls(), 1u);
  watch.beat("stepping", 0.012, 201.0);  // it moved again ...
  EXPECT_FALSE(watch.checkStall(202.0, &report));
  EXPECT_TRUE(watch.checkStall(206.5, &report));  // ... and stopped again: a new stall
  EXPECT_EQ(watch.stalls(), 2u);
}

TEST(LoopWatch, RefusesANonPositiveLimit) {
  EXPECT_THROW(LoopWatch(0.0), std::invalid_argument);
  EXPECT_THROW(LoopWatch(-1.0), std::invalid_argument);
}
