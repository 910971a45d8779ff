// Lock-step bookkeeping without ROS: answers owed per trigger, chains, rates, timeouts.
#include <gtest/gtest.h>

#include "conde_sim/lockstep_frames.h"

namespace cs = conde_sim;

namespace {

cs::LockstepRule rule(const std::string& answer, std::vector<std::string> triggers, double rate_hz = 0.0) {
  cs::LockstepRule r;
  r.answer_topic = answer;
  r.trigger_topics = std::move(triggers);
  r.rate_hz = rate_hz;
  return r;
}

}  // namespace

TEST(LockstepFrames, WaitsForTheAnswerOfATrigger) {
  cs::LockstepFrames frames({rule("/lane", {"/image"})}, 1.0);
  EXPECT_FALSE(frames.waiting());
  frames.onMessage("/image", 0.033, 10.0);
  EXPECT_TRUE(frames.waiting());
  EXPECT_EQ(frames.missing(), "/lane (answers /image)");
  frames.onMessage("/other", 0.033, 10.1);
  EXPECT_TRUE(frames.waiting());
  frames.onMessage("/lane", 0.033, 10.2);
  EXPECT_FALSE(frames.waiting());
  EXPECT_EQ(frames.frames(), 1u);
  EXPECT_EQ(frames.stats(0).triggers, 1u);
  EXPECT_EQ(frames.stats(0).answered, 1u);
  EXPECT_EQ(frames.stats(0).timeouts, 0u);
}

TEST(LockstepFrames, TriggersOfOneFrameOweOneAnswer) {
  cs::LockstepFrames frames({rule("/lane", {"/left", "/right"})}, 1.0);
  frames.onMessage("/left", 0.033, 0.0);
  frames.onMessage("/right", 0.033, 0.0);
  frames.onMessage("/lane", 0.033, 0.01);
  EXPECT_FALSE(frames.waiting());
  EXPECT_EQ(frames.stats(0).triggers, 1u);
}

TEST(LockstepFrames, AnAnswerBeforeItsTriggerIsNotKept) {
  cs::LockstepFrames frames({rule("/lane", {"/image"})}, 1.0);
  frames.onMessage("/lane", 0.0, 0.0);
  EXPECT_EQ(frames.stats(0).unsolicited, 1u);
  frames.onMessage("/image", 0.033, 0.0);
  EXPECT_TRUE(frames.waiting());
}

TEST(LockstepFrames, AChainLinkThatOvertakesItsTriggerCountsInTheSameWait) {
  cs::LockstepFrames frames({rule("/lane", {"/image"}), rule("/reference", {"/lane"})}, 1.0);
  frames.onMessage("/image", 0.033, 0.0);
  frames.onMessage("/reference", 0.033, 0.01);  // on its own connection, before /lane
  EXPECT_TRUE(frames.waiting());
  frames.onMessage("/lane", 0.033, 0.02);
  EXPECT_FALSE(frames.waiting());
  EXPECT_EQ(frames.stats(1).answered, 1u);
  EXPECT_EQ(frames.stats(1).unsolicited, 0u);
  // An early answer whose trigger never comes is not kept past its wait.
  frames.onMessage("/image", 0.066, 1.0);
  frames.onMessage("/reference", 0.066, 1.01);
  EXPECT_TRUE(frames.checkTimeout(2.0));
  EXPECT_EQ(frames.stats(1).unsolicited, 1u);
  frames.onMessage("/image", 0.1, 3.0);
  frames.onMessage("/lane", 0.1, 3.01);
  EXPECT_TRUE(frames.waiting());  // owes /reference again
}

TEST(LockstepFrames, ChainsWaitForEveryLink) {
  cs::LockstepFrames frames({rule("/lane", {"/image"}), rule("/reference", {"/lane"})}, 1.0);
  frames.onMessage("/image", 0.033, 0.0);
  frames.onMessage("/lane", 0.033, 0.01);  // answers the image, triggers the decision
  EXPECT_TRUE(frames.waiting());
  EXPECT_EQ(frames.missing(), "/reference (answers /lane)");
  frames.onMessage("/reference", 0.033, 0.02);
  EXPECT_FALSE(frames.waiting());
  EXPECT_EQ(frames.frames(), 1u);  // one wait
}

TEST(LockstepFrames, TimeoutGivesUpAndCounts) {
  cs::LockstepFrames frames({rule("/lane", {"/image"}), rule("/signal", {"/image"})}, 0.5);
  for (int frame = 0; frame < 3; ++frame) {
    const double wall_s = 10.0 * frame;
    frames.onMessage("/image", 0.033 * frame, wall_s);
    frames.onMessage("/signal", 0.033 * frame, wall_s + 0.1);
    EXPECT_FALSE(frames.checkTimeout(wall_s + 0.49));
    EXPECT_TRUE(frames.waiting());
    EXPECT_TRUE(frames.checkTimeout(wall_s + 0.5));  // never a deadlock
    EXPECT_FALSE(frames.waiting());
  }
  EXPECT_EQ(frames.timedOutFrames(), 3u);
  EXPECT_EQ(frames.stats(0).timeouts, 3u);
  EXPECT_EQ(frames.stats(1).timeouts, 0u);
  EXPECT_EQ(frames.stats(1).answered, 3u);
  // A late answer is not kept for the next frame.
  frames.onMessage("/lane", 0.1, 31.0);
  EXPECT_EQ(frames.stats(0).unsolicited, 1u);
  EXPECT_FALSE(frames.waiting());
}

TEST(LockstepFrames, NoTimeoutWhileNotWaiting) {
  cs::LockstepFrames frames({rule("/lane", {"/image"})}, 0.5);
  EXPECT_FALSE(frames.checkTimeout(100.0));
  EXPECT_EQ(frames.timedOutFrames(), 0u);
}

TEST(LockstepFrames, RateFollowsRospyRateOnTheClock) {
  // /clock at 100 Hz, a node at rospy.Rate(30) from t = 0: it wakes at the first /clock at or
  // after k / 30 s: 0.04, 0.07, 0.10, 0.14, 0.17, 0.20.
  cs::LockstepFrames frames({rule("/cmd_vel", {"/clock"}, 30.0)}, 1.0);
  std::vector<int> owed_at;
  for (int k = 1; k <= 20; ++k) {
    frames.onMessage("/clock", 0.01 * k, 0.0);
    if (frames.waiting()) {
      owed_at.push_back(k);
      frames.onMessage("/cmd_vel", 0.01 * k, 0.0);
    }
  }
  EXPECT_EQ(owed_at, (std::vector<int>{4, 7, 10, 14, 17, 20}));
}

TEST(LockstepFrames, SlowerAnswerRateOwesFewerAnswers) {
  // Images at 30 Hz, a node that answers at 10 Hz: one answer for every third image.
  cs::LockstepFrames frames({rule("/slow", {"/image"}, 10.0)}, 1.0);
  int owed = 0;
  for (int k = 1; k <= 30; ++k) {
    frames.onMessage("/image", k / 30.0, 0.0);
    if (frames.waiting()) {
      ++owed;
      frames.onMessage("/slow", k / 30.0, 0.0);
    }
  }
  EXPECT_EQ(owed, 10);
}

TEST(LockstepFrames, SilentAtStartUpWhenAsked) {
  cs::LockstepRule r = rule("/signal", {"/image"});
  r.wait_for_first_answer = false;
  cs::LockstepFrames frames({r}, 1.0);
  frames.onMessage("/image", 0.033, 0.0);
  EXPECT_FALSE(frames.waiting());  // not owed before its first answer
  frames.onMessage("/signal", 0.05, 0.0);
  frames.onMessage("/image", 0.066, 0.0);
  EXPECT_TRUE(frames.waiting());
}

TEST(LockstepFrames, ResetForgetsWhatIsOwed) {
  cs::LockstepFrames frames({rule("/cmd_vel", {"/clock"}, 10.0)}, 1.0);
  frames.onMessage("/clock", 0.1, 0.0);
  EXPECT_TRUE(frames.waiting());
  frames.reset();
  EXPECT_FALSE(frames.waiting());
  frames.onMessage("/clock", 0.05, 0.0);  // deadlines restart at 0
  EXPECT_FALSE(frames.waiting());
  frames.onMessage("/clock", 0.1, 0.0);
  EXPECT_TRUE(frames.waiting());
}

TEST(LockstepFrames, TopicsToWatchLeaveTheClockOut) {
  cs::LockstepFrames frames({rule("/lane", {"/b", "/a"}), rule("/cmd_vel", {"/clock"}, 30.0)}, 1.0);
  EXPECT_EQ(frames.topicsToWatch(), (std::vector<std::string>{"/a", "/b", "/cmd_vel", "/lane"}));
}

TEST(LockstepFrames, BadRulesAreRefused) {
  EXPECT_THROW(cs::LockstepFrames({rule("/lane", {})}, 1.0), std::invalid_argument);
  EXPECT_THROW(cs::LockstepFrames({rule("", {"/image"})}, 1.0), std::invalid_argument);
  EXPECT_THROW(cs::LockstepFrames({rule("/lane", {"/image"})}, 0.0), std::invalid_argument);
  EXPECT_THROW(cs::LockstepFrames({rule("/lane", {"/image"}, -1.0)}, 1.0), std::invalid_argument);
}
