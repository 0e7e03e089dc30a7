#include "config/stop_signal.hpp"

#include "socketlib/socketlib.h"

namespace config {

namespace {
volatile std::sig_atomic_t g_stop = 0;

extern "C" void on_stop_signal(int signo) { g_stop = signo; }
}  // namespace

void install_stop_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  // No SA_RESTART: a blocking wait returns EINTR and looks at the flag.
  // SA_RESETHAND: the next signal of the same kind takes the default action.
  sa.sa_flags = SA_RESETHAND;
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaction(s, &sa, nullptr);
  sl_set_stop_flag(&g_stop);
}

int stop_signal() { return static_cast<int>(g_stop); }

std::string signal_name(int signo) {
  switch (signo) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "signal " + std::to_string(signo);
  }
}

}  // namespace config
