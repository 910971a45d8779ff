#include "conde_sim/thread_backtraces.h"

#include <dirent.h>
#include <execinfo.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace conde_sim {

namespace {

constexpr int kMaxFrames = 64;
std::atomic<int> g_fd{-1};
std::atomic<bool> g_written{false};

void writeOwnStack(int fd) {
  void* frames[kMaxFrames];
  const int n = backtrace(frames, kMaxFrames);
  backtrace_symbols_fd(frames, n, fd);
}

void onBacktraceSignal(int) {
  const int saved_errno = errno;
  const int fd = g_fd.load();
  if (fd >= 0) writeOwnStack(fd);
  g_written.store(true);
  errno = saved_errno;
}

void writeText(int fd, const std::string& text) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n <= 0) return;
    done += static_cast<size_t>(n);
  }
}

std::string threadName(pid_t tid) {
  std::ifstream in("/proc/self/task/" + std::to_string(tid) + "/comm");
  std::string name;
  std::getline(in, name);
  return name;
}

std::vector<pid_t> threadIds() {
  std::vector<pid_t> tids;
  if (DIR* dir = opendir("/proc/self/task")) {
    while (const dirent* entry = readdir(dir)) {
      if (entry->d_name[0] != '.') tids.push_back(static_cast<pid_t>(std::atoi(entry->d_name)));
    }
    closedir(dir);
  }
  return tids;
}

}  // namespace

void installThreadBacktraceHandler() {
  void* frames[1];
  backtrace(frames, 1);  // loads libgcc's unwinder now, not inside the handler
  struct sigaction action {};
  action.sa_handler = onBacktraceSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGUSR2, &action, nullptr);
}

int writeThreadBacktraces(int fd, double per_thread_timeout_s) {
  const pid_t pid = getpid();
  const auto self = static_cast<pid_t>(syscall(SYS_gettid));
  int answered = 0;
  for (const pid_t tid : threadIds()) {
    writeText(fd, "thread " + std::to_string(tid) + " (" + threadName(tid) + ")" +
                      (tid == self ? " (this thread)" : "") + ":\n");
    if (tid == self) {
      writeOwnStack(fd);
      ++answered;
      continue;
    }
    g_fd.store(fd);
    g_written.store(false);
    if (syscall(SYS_tgkill, pid, tid, SIGUSR2) != 0) {
      writeText(fd, "  (gone)\n");
      continue;
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(per_thread_timeout_s);
    while (!g_written.load() && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (g_written.load()) {
      ++answered;
    } else {
      writeText(fd, "  (no answer: the signal is blocked or the thread is stopped)\n");
    }
  }
  g_fd.store(-1);
  return answered;
}

}  // namespace conde_sim
