#include "conde_sim/loop_watch.h"

#include <cstdio>
#include <stdexcept>

namespace conde_sim {

LoopWatch::LoopWatch(double stall_after_s) : stall_after_s_(stall_after_s) {
  if (!(stall_after_s_ > 0)) throw std::invalid_argument("loop watch: stall_after_s must be > 0");
}

void LoopWatch::beat(const char* phase, double sim_time_s, double wall_s) {
  phase_.store(phase, std::memory_order_relaxed);
  sim_time_s_.store(sim_time_s, std::memory_order_relaxed);
  last_beat_wall_s_.store(wall_s, std::memory_order_relaxed);
  beats_.fetch_add(1, std::memory_order_release);
}

bool LoopWatch::checkStall(double wall_s, std::string* report) {
  const std::uint64_t beats = beats_.load(std::memory_order_acquire);
  const double last = last_beat_wall_s_.load(std::memory_order_relaxed);
  if (last < 0 || wall_s - last < stall_after_s_ || beats == reported_beats_) return false;
  reported_beats_ = beats;
  stalls_.fetch_add(1);
  if (report) {
    char text[256];
    std::snprintf(text, sizeof(text), "the step loop has not moved for %.1f s of wall time, at t = %.3f s, in: %s",
                  wall_s - last, sim_time_s_.load(std::memory_order_relaxed), phase_.load(std::memory_order_relaxed));
    *report = text;
  }
  return true;
}

}  // namespace conde_sim
