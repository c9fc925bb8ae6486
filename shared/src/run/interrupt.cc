// Signal handlers of interrupt.h: async-signal-safe (a sig_atomic_t flag, write(2), _exit).
#include "grainlift/shared/run/interrupt.h"

#include <csignal>
#include <cstring>

#include <unistd.h>

namespace grainlift {

namespace {

volatile std::sig_atomic_t g_signal = 0;

void on_signal(int sig) {
  if (g_signal != 0) _exit(128 + sig);  // the second signal: at once, nothing written
  g_signal = sig;
  static const char msg[] =
      "\ngrainlift: stopping at the next step boundary and writing what the run has so far "
      "(signal again to quit at once)\n";
  const ssize_t ignored = write(STDERR_FILENO, msg, sizeof msg - 1);
  (void)ignored;
}

}  // namespace

void install_interrupt_handlers() {
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int interrupt_signal() { return g_signal; }

void set_interrupt_signal(int sig) { g_signal = sig; }

}  // namespace grainlift
