// fe_server's exit codes, distinct per cause so scripts and tests can tell
// them apart. Documented in the README.
#pragma once

#include "config/stop_signal.hpp"

namespace fe {

enum ExitCode : int {
  kExitOk = 0,             // session ended with BYE (or a standalone run finished)
  kExitUsage = 2,          // bad command line
  kExitInput = 3,          // deck or port configuration rejected (file:line in the message)
  kExitAcceptTimeout = 4,  // no host connected before --accept-timeout
  kExitHandshake = 5,      // a handshake refused (version, port table, time step, token); the
                           // server logs it and keeps listening, so it no longer exits with 5
  kExitLinkLost = 6,       // peer closed, stalled past the step deadline, or sent garbage
  kExitPeerAbort = 7,      // the host sent ABORT
  kExitNumerical = 8,      // NaN/Inf in an input or in the FE state
  kExitInternal = 9,       // anything else (a bug: please report)
  kExitCheckpointed = 10,  // the host stopped the session right after both sides checkpointed
                           // (--restart continues it)
  kExitEnergy = 11,        // finished, but the energy account is beyond its bound: the results
                           // are kept and not to be trusted (--accept-energy-error waives it)
  kExitStopped = 128,      // + the signal's number: stopped by SIGINT (130), SIGTERM (143) or
                           // SIGHUP (129), results flushed and the host told
};

}  // namespace fe

namespace fe {
inline ExitCode stopped_by(int signo) { return static_cast<ExitCode>(config::stop_exit_code(signo)); }
}  // namespace fe
