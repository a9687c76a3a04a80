#include "cli/interrupt.h"

#include <csignal>
#include <cstdio>
#include <cstring>
#include <thread>

#include <pthread.h>
#include <unistd.h>

#include "io/atomic_file.h"

namespace clothbake::cli {

namespace {

sigset_t interrupt_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGHUP);
  return set;
}

// A plain thread rather than a signal handler: removing folders is not
// async-signal-safe, and here it need not be.
[[noreturn]] void wait_for_interrupt(sigset_t set) {
  int sig = 0;
  while (sigwait(&set, &sig) != 0) {
  }
  const int removed = io::remove_unfinished_outputs_and_freeze();
  std::fprintf(stderr,
               "clothbake: interrupted by %s: stopped; %d unfinished output%s removed, earlier "
               "outputs left as they were\n",
               sig == SIGTERM  ? "SIGTERM"
               : sig == SIGINT ? "SIGINT"
                               : "SIGHUP",
               removed, removed == 1 ? "" : "s");
  std::fflush(stderr);
  ::_exit(128 + sig);
}

}  // namespace

void install_interrupt_handler() {
  const sigset_t set = interrupt_signals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread(wait_for_interrupt, set).detach();
}

}  // namespace clothbake::cli
