#include "conde_sim/message_counts.h"

#include <gtest/gtest.h>

#include <string>

using conde_sim::MessageCounts;

TEST(MessageCounts, AnUnwatchedTopicIsNotCounted) {
  MessageCounts counts;
  counts.onMessage("/cmd_vel", "/driver");
  EXPECT_EQ(counts.received("/cmd_vel", "/driver"), 0u);
  EXPECT_TRUE(counts.watch("/cmd_vel"));
  EXPECT_FALSE(counts.watch("/cmd_vel"));                 // subscribed once
  EXPECT_EQ(counts.received("/cmd_vel", "/driver"), 0u);  // what came before is not counted
}

TEST(MessageCounts, CountsPerTopicAndPublisher) {
  MessageCounts counts;
  counts.watch("/cmd_vel");
  counts.watch("/arm/command");
  counts.onMessage("/cmd_vel", "/driver");
  counts.onMessage("/cmd_vel", "/driver");
  counts.onMessage("/cmd_vel", "/teleop");
  counts.onMessage("/arm/command", "/driver");
  EXPECT_EQ(counts.received("/cmd_vel", "/driver"), 2u);
  EXPECT_EQ(counts.received("/cmd_vel", "/teleop"), 1u);
  EXPECT_EQ(counts.received("/arm/command", "/driver"), 1u);
  EXPECT_EQ(counts.received("/arm/command", "/teleop"), 0u);
}

TEST(MessageCounts, ARequestIsMetOnceItsCountHasArrived) {
  MessageCounts counts;
  counts.watch("/cmd_vel");
  const auto baseline = counts.received("/cmd_vel", "/driver");
  EXPECT_TRUE(counts.met("/cmd_vel", "/driver", baseline));  // count 0 / the baseline: at once
  EXPECT_FALSE(counts.met("/cmd_vel", "/driver", baseline + 1));
  counts.onMessage("/cmd_vel", "/teleop");  // another node's message acknowledges nothing of /driver's
  EXPECT_FALSE(counts.met("/cmd_vel", "/driver", baseline + 1));
  counts.onMessage("/cmd_vel", "/driver");
  EXPECT_TRUE(counts.met("/cmd_vel", "/driver", baseline + 1));
  EXPECT_FALSE(counts.met("/cmd_vel", "/driver", baseline + 2));
}

TEST(MessageCounts, TheTimeoutErrorNamesTopicNodeAndCounts) {
  MessageCounts counts;
  counts.watch("/cmd_vel");
  counts.onMessage("/cmd_vel", "/driver");
  const std::string error = counts.describeMissing("/cmd_vel", "/driver", 3, 30.0);
  EXPECT_NE(error.find("received 1 of 3 messages on /cmd_vel from /driver within 30.000 s"), std::string::npos)
      << error;
}
