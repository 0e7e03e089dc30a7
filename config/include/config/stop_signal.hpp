// SIGINT, SIGTERM and SIGHUP as a request to stop cleanly. The handler only
// records the signal; the programs look at stop_signal() at safe points (each
// coupling or time step, and socketlib's waits, which wake every 200 ms to
// look), flush their results, tell the peer through ABORT and exit with
// 128 + the signal's number, as a shell reports a process killed by it
// (130 for Ctrl-C, 143 for SIGTERM). A stop that takes time of its own (a
// checkpoint of both sides at SIGTERM) lets its waits run on past the first
// signal and ends them at the second (second_stop_flag), still cleaning up;
// a third ends the process at once (the default action).
#pragma once

#include <csignal>
#include <stdexcept>
#include <string>

namespace config {

// Installs the handlers and hands socketlib the flag (sl_set_stop_flag).
void install_stop_handlers();
// The signal that asked to stop, or 0.
int stop_signal();
// Set (to its number) by the second stop signal: for sl_set_stop_flag where
// the first signal must not end the waits.
const volatile std::sig_atomic_t* second_stop_flag();
// "SIGINT", "SIGTERM", ...
std::string signal_name(int signo);
// The exit code for a stop by `signo`.
inline int stop_exit_code(int signo) { return 128 + signo; }

// Thrown at a safe point once a stop was requested.
class StopRequested : public std::runtime_error {
 public:
  explicit StopRequested(int signo)
      : std::runtime_error("stopped by " + signal_name(signo)), signo_(signo) {}
  StopRequested(int signo, const std::string& what) : std::runtime_error(what), signo_(signo) {}
  int signo() const { return signo_; }

 private:
  int signo_;
};

}  // namespace config
