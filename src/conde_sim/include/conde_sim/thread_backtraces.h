// The call stack of every thread of this process, written to a file descriptor (Linux, glibc's
// backtrace): when the step loop is stuck, the log then says where each thread waits (a lock, a
// socket, a condition) instead of only that nothing moves.
//
//   installThreadBacktraceHandler();          // once, at start-up
//   writeThreadBacktraces(STDERR_FILENO, 1.0); // later, from any thread
//
// Each other thread is asked in turn by a signal (SIGUSR2) whose handler writes its own stack;
// one that does not answer within the timeout (signal blocked, stopped) is named as such. Symbol
// names need the program linked with -rdynamic (ENABLE_EXPORTS); otherwise addresses show.
#pragma once

namespace conde_sim {

// Installs the SIGUSR2 handler and loads the unwinder (backtrace() allocates on its first call,
// which a signal handler must not do). Safe to call more than once.
void installThreadBacktraceHandler();

// Writes "thread <tid> (<name>)[ (this thread)]:" and its frames for every thread, waiting at most
// per_thread_timeout_s [s of wall time] for each. Returns how many threads wrote their stack.
// Not reentrant: one caller at a time.
int writeThreadBacktraces(int fd, double per_thread_timeout_s);

}  // namespace conde_sim
