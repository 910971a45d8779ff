// Watches the step loop from another thread, without ROS: the loop thread says where it is and
// that it moves (beat()); a watcher thread asks checkStall() with the wall clock. A loop that has
// not beaten for stall_after_s is stuck in the phase it last named: reported once per stall, so a
// hang is never silent (a lock-step frame waits at most its timeout, a paused loop beats every few
// ms, so no healthy loop stands still that long).
//
//   LoopWatch watch(30.0);                           // 30 s of wall time without a beat = stuck
//   watch.beat("stepping", sim_time_s, wall_s);      // loop thread, at each phase
//   std::string report;
//   if (watch.checkStall(wall_s, &report)) log(report);  // watcher thread, e.g. once a second
//
// Phases are string literals (only the pointer is kept). Thread-safe: atomics only.
#pragma once

#include <atomic>
#include <string>

namespace conde_sim {

class LoopWatch {
 public:
  // stall_after_s: wall-clock time without a beat that counts as stuck [s] (> 0).
  explicit LoopWatch(double stall_after_s);

  // The loop is in `phase` (a string literal) at simulated time sim_time_s [s], wall time wall_s [s].
  void beat(const char* phase, double sim_time_s, double wall_s);

  // True once per stall (the next beat ends it): report says how long, where and at what time.
  bool checkStall(double wall_s, std::string* report);

  double stallAfterS() const { return stall_after_s_; }
  std::uint64_t stalls() const { return stalls_.load(); }

 private:
  double stall_after_s_;
  std::atomic<const char*> phase_{"starting"};
  std::atomic<double> sim_time_s_{0.0};
  std::atomic<double> last_beat_wall_s_{-1.0};  // < 0: no beat yet (start-up is not watched)
  std::atomic<std::uint64_t> beats_{0};
  std::uint64_t reported_beats_ = ~std::uint64_t(0);  // watcher thread only
  std::atomic<std::uint64_t> stalls_{0};
};

}  // namespace conde_sim
