// Acknowledged delivery, without ROS: how many messages the simulator has received on a topic from
// each publishing node, and whether a node's request "wait until you have my `count` messages on
// `topic`" is met. The node (sim_node.cpp, service ~wait_for_messages) feeds it from a counting
// subscription on the loop's callback queue and asks it from the service thread, under its mutex.
//
//   MessageCounts counts;
//   counts.watch("/cmd_vel");                          // the first request naming the topic
//   counts.received("/cmd_vel", "/odometry_test");     // 0: the baseline
//   counts.onMessage("/cmd_vel", "/odometry_test");    // a message from that node arrived
//   counts.met("/cmd_vel", "/odometry_test", 1);       // true
//
// Counts start when a topic is first watched: a message published before then, or still in
// flight then, is counted if it arrives after it. A caller takes its baseline with nothing of its
// own in flight on the topic (every earlier message acknowledged, or none sent yet).
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>

namespace conde_sim {

class MessageCounts {
 public:
  // Starts counting `topic`; returns true the first time (the caller then subscribes to it).
  bool watch(const std::string& topic);
  bool watched(const std::string& topic) const { return topics_.count(topic) > 0; }

  // A message on a watched `topic` from the node `publisher` (its caller id); others are ignored.
  void onMessage(const std::string& topic, const std::string& publisher);

  std::uint64_t received(const std::string& topic, const std::string& publisher) const;
  bool met(const std::string& topic, const std::string& publisher, std::uint64_t count) const {
    return received(topic, publisher) >= count;
  }

  // The error of a request that timed out, naming the topic, the node and both counts.
  std::string describeMissing(const std::string& topic, const std::string& publisher, std::uint64_t count,
                              double timeout_s) const;

 private:
  std::set<std::string> topics_;
  std::map<std::pair<std::string, std::string>, std::uint64_t> counts_;
};

}  // namespace conde_sim
