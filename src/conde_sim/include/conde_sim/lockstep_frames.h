// Lock-step bookkeeping, without ROS: which answers the simulation still waits for before it takes
// its next step. The node feeds it every message it sees on a configured topic (and every /clock
// it publishes); while waiting() is true it does not step, and it asks checkTimeout() with the
// wall clock so that a silent node never stops the run.
//
//   LockstepRule lane;
//   lane.answer_topic = "/conde_lane";                 // what the node publishes
//   lane.trigger_topics = {"/camera/image_raw"};       // what it answers, once per message
//   LockstepFrames frames({lane}, 1.0);                // 1 s of wall time per frame at most
//   frames.onMessage("/camera/image_raw", t_s, wall_s); // the simulator published an image
//   frames.waiting();                                   // true until /conde_lane comes
//   frames.onMessage("/conde_lane", t_s, wall_s);       // -> false
//
// An answer counts when it arrives while its rule owes one (one message on the answer topic since
// the trigger). One that arrives during a wait before its trigger (a chain's link whose trigger
// comes on another connection) is kept until that wait ends; any other answer nobody owes is
// counted as unsolicited and not kept for later. A topic
// may be the answer of one rule and the trigger of another (chains: /conde_lane answers the
// cameras and triggers the decision's /conde_control_reference); the wait goes on until the
// whole chain has answered. A rule with rate_hz > 0 owes one answer per period of simulated time,
// as a node driven by rospy.Rate(rate_hz) on /clock started at simulated time 0: the first
// trigger at or after each deadline owes one, and the deadlines advance as rospy.Rate's do.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace conde_sim {

struct LockstepRule {
  std::string answer_topic;                 // resolved topic name the node publishes
  std::vector<std::string> trigger_topics;  // resolved topic names it answers ("/clock" included)
  double rate_hz = 0.0;                     // > 0: at most one answer per 1 / rate_hz simulated s
  // false: nothing is owed before the first answer (nodes that stay silent at start-up, such as a
  // debouncing classifier); true: a node that never answers times out at every trigger.
  bool wait_for_first_answer = true;
};

struct LockstepRuleStats {
  std::uint64_t triggers = 0;     // answers owed
  std::uint64_t answered = 0;     // owed answers that came
  std::uint64_t timeouts = 0;     // owed answers given up at a timeout
  std::uint64_t unsolicited = 0;  // answers nobody owed
};

class LockstepFrames {
 public:
  // timeout_s: wall-clock time a frame may wait for its answers [s] (> 0).
  LockstepFrames(std::vector<LockstepRule> rules, double timeout_s);

  // A message on `topic` seen at simulated time sim_time_s [s], wall time wall_s [s] (any
  // monotonic clock). It first answers, then triggers.
  void onMessage(const std::string& topic, double sim_time_s, double wall_s);

  // True while an answer is owed: the simulation must not step.
  bool waiting() const;
  // When waiting for longer than the timeout: gives up every owed answer (counted per rule and as
  // one timed-out frame) and returns true; the simulation goes on with what it has.
  bool checkTimeout(double wall_s);
  // Forget what is owed and restart the rate deadlines (world reset: simulated time restarts).
  void reset();

  // Every topic the node must subscribe to (answers and triggers, without "/clock"), sorted.
  std::vector<std::string> topicsToWatch() const;
  const std::vector<LockstepRule>& rules() const { return rules_; }
  const LockstepRuleStats& stats(std::size_t rule) const { return rules_state_[rule].stats; }
  std::uint64_t frames() const { return frames_; }  // waits begun
  std::uint64_t timedOutFrames() const { return timed_out_frames_; }
  double timeoutS() const { return timeout_s_; }
  // "/conde_lane (answers /camera/image_raw)" for each rule still owed, comma-separated.
  std::string missing() const;

 private:
  struct RuleState {
    std::uint64_t owed = 0;
    std::uint64_t early = 0;  // an answer that came, during this wait, before its trigger
    bool answered_once = false;
    double last_deadline_s = 0.0;  // rospy.Rate's last_time
    LockstepRuleStats stats;
  };

  void endFrame();  // the wait is over: early answers left are unsolicited

  std::vector<LockstepRule> rules_;
  std::vector<RuleState> rules_state_;
  double timeout_s_;
  double wait_start_wall_s_ = 0.0;
  std::uint64_t frames_ = 0, timed_out_frames_ = 0;
};

}  // namespace conde_sim
