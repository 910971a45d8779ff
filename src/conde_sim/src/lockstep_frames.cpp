#include "conde_sim/lockstep_frames.h"

#include <algorithm>
#include <set>
#include <stdexcept>

namespace conde_sim {

LockstepFrames::LockstepFrames(std::vector<LockstepRule> rules, double timeout_s)
    : rules_(std::move(rules)), rules_state_(rules_.size()), timeout_s_(timeout_s) {
  if (!(timeout_s_ > 0)) throw std::invalid_argument("lock-step: timeout_s must be > 0");
  for (const LockstepRule& rule : rules_) {
    if (rule.answer_topic.empty()) throw std::invalid_argument("lock-step: a rule without an answer topic");
    if (rule.trigger_topics.empty()) {
      throw std::invalid_argument("lock-step: " + rule.answer_topic + " answers no topic");
    }
    if (!(rule.rate_hz >= 0)) throw std::invalid_argument("lock-step: " + rule.answer_topic + ": rate_hz must be >= 0");
  }
}

void LockstepFrames::onMessage(const std::string& topic, double sim_time_s, double wall_s) {
  const bool was_waiting = waiting();
  for (std::size_t i = 0; i < rules_.size(); ++i) {
    if (rules_[i].answer_topic != topic) continue;
    RuleState& state = rules_state_[i];
    state.answered_once = true;
    if (state.owed > 0) {
      --state.owed;
      ++state.stats.answered;
    } else if (was_waiting && state.early == 0) {
      state.early = 1;  // its trigger may still be on its way (another connection)
    } else {
      ++state.stats.unsolicited;
    }
  }
  for (std::size_t i = 0; i < rules_.size(); ++i) {
    const LockstepRule& rule = rules_[i];
    if (std::find(rule.trigger_topics.begin(), rule.trigger_topics.end(), topic) == rule.trigger_topics.end()) continue;
    RuleState& state = rules_state_[i];
    if (rule.rate_hz > 0) {
      // rospy.Rate: wakes at the first time >= last + period, then last += period, or last = now
      // when more than two periods behind.
      const double period_s = 1.0 / rule.rate_hz;
      if (sim_time_s < state.last_deadline_s + period_s - 1e-9) continue;
      state.last_deadline_s += period_s;
      if (sim_time_s - state.last_deadline_s > 2 * period_s) state.last_deadline_s = sim_time_s;
    }
    if (!rule.wait_for_first_answer && !state.answered_once) continue;
    // Triggers that come together (both cameras of one frame) owe one answer.
    if (state.owed == 0) {
      ++state.stats.triggers;
      if (state.early > 0) {
        state.early = 0;
        ++state.stats.answered;
      } else {
        state.owed = 1;
      }
    }
  }
  if (!was_waiting && waiting()) {
    wait_start_wall_s_ = wall_s;
    ++frames_;
  }
  if (!waiting()) endFrame();
}

void LockstepFrames::endFrame() {
  for (RuleState& state : rules_state_) {
    state.stats.unsolicited += state.early;
    state.early = 0;
  }
}

bool LockstepFrames::waiting() const {
  return std::any_of(rules_state_.begin(), rules_state_.end(), [](const RuleState& s) { return s.owed > 0; });
}

bool LockstepFrames::checkTimeout(double wall_s) {
  if (!waiting() || wall_s - wait_start_wall_s_ < timeout_s_) return false;
  for (RuleState& state : rules_state_) {
    state.stats.timeouts += state.owed;
    state.owed = 0;
  }
  ++timed_out_frames_;
  endFrame();
  return true;
}

void LockstepFrames::reset() {
  for (RuleState& state : rules_state_) {
    state.owed = 0;
    state.early = 0;
    state.last_deadline_s = 0.0;
  }
}

std::vector<std::string> LockstepFrames::topicsToWatch() const {
  std::set<std::string> topics;
  for (const LockstepRule& rule : rules_) {
    topics.insert(rule.answer_topic);
    for (const std::string& t : rule.trigger_topics)
      if (t != "/clock") topics.insert(t);
  }
  return {topics.begin(), topics.end()};
}

std::string LockstepFrames::missing() const {
  std::string text;
  for (std::size_t i = 0; i < rules_.size(); ++i) {
    if (rules_state_[i].owed == 0) continue;
    std::string triggers;
    for (const std::string& t : rules_[i].trigger_topics) triggers += (triggers.empty() ? "" : ", ") + t;
    text += (text.empty() ? "" : ", ") + rules_[i].answer_topic + " (answers " + triggers + ")";
  }
  return text;
}

}  // namespace conde_sim
