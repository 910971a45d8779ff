#include "conde_sim/thread_backtraces.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <condition_variable>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>

namespace {

std::mutex g_mutex;
std::condition_variable g_cv;
bool g_release = false, g_parked = false;

}  // namespace

// Where the other thread waits; exported (the test links with -rdynamic) so its name shows.
extern "C" __attribute__((noinline)) void conde_sim_test_parked_thread() {
  std::unique_lock<std::mutex> lock(g_mutex);
  g_parked = true;
  g_cv.notify_all();
  g_cv.wait(lock, [] { return g_release; });
}

TEST(ThreadBacktraces, EveryThreadWritesWhereItWaits) {
  conde_sim::installThreadBacktraceHandler();
  std::thread parked(conde_sim_test_parked_thread);
  {
    std::unique_lock<std::mutex> lock(g_mutex);
    g_cv.wait(lock, [] { return g_parked; });
  }
  char path[] = "/tmp/conde_sim_backtraces_XXXXXX";
  const int fd = mkstemp(path);
  ASSERT_GE(fd, 0);
  const int answered = conde_sim::writeThreadBacktraces(fd, 5.0);
  close(fd);
  {
    std::lock_guard<std::mutex> lock(g_mutex);
    g_release = true;
  }
  g_cv.notify_all();
  parked.join();
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  unlink(path);
  const std::string out = text.str();
  EXPECT_GE(answered, 2) << out;
  EXPECT_NE(out.find("(this thread):"), std::string::npos) << out;
  EXPECT_NE(out.find("conde_sim_test_parked_thread"), std::string::npos) << out;
  size_t headers = 0;
  for (size_t at = out.find("thread "); at != std::string::npos; at = out.find("\nthread ", at + 1)) ++headers;
  EXPECT_EQ(headers, static_cast<size_t>(answered)) << out;
}
