#include "config/stop_signal.hpp"

#include <csignal>

#include "socketlib/socketlib.h"

namespace config {

namespace {
volatile std::sig_atomic_t g_stop = 0;   // the first stop signal
volatile std::sig_atomic_t g_hurry = 0;  // the second

// Only async-signal-safe calls here (signal, raise).
extern "C" void on_stop_signal(int signo) {
  if (g_stop == 0) {
    g_stop = signo;
  } else if (g_hurry == 0) {
    g_hurry = signo;
  } else {  // the third: the default action, at once
    std::signal(signo, SIG_DFL);
    std::raise(signo);
  }
}
}  // namespace

void install_stop_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  // No SA_RESTART: a blocking wait returns EINTR and looks at the flag.
  sa.sa_flags = 0;
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaction(s, &sa, nullptr);
  sl_set_stop_flag(&g_stop);
}

int stop_signal() { return static_cast<int>(g_stop); }

const volatile std::sig_atomic_t* second_stop_flag() { return &g_hurry; }

std::string signal_name(int signo) {
  switch (signo) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "signal " + std::to_string(signo);
  }
}

}  // namespace config
