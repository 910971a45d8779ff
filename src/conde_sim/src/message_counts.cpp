#include "conde_sim/message_counts.h"

#include <cstdio>

namespace conde_sim {

bool MessageCounts::watch(const std::string& topic) { return topics_.insert(topic).second; }

void MessageCounts::onMessage(const std::string& topic, const std::string& publisher) {
  if (watched(topic)) ++counts_[{topic, publisher}];
}

std::uint64_t MessageCounts::received(const std::string& topic, const std::string& publisher) const {
  const auto it = counts_.find({topic, publisher});
  return it == counts_.end() ? 0 : it->second;
}

std::string MessageCounts::describeMissing(const std::string& topic, const std::string& publisher, std::uint64_t count,
                                           double timeout_s) const {
  char timeout[32];
  std::snprintf(timeout, sizeof timeout, "%.3f", timeout_s);
  return "received " + std::to_string(received(topic, publisher)) + " of " + std::to_string(count) + " messages on " +
         topic + " from " + publisher + " within " + timeout + " s of wall time (is " + publisher +
         " connected to the simulator on " + topic + "?)";
}

}  // namespace conde_sim
