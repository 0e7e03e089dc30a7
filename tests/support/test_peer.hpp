// An in-process stand-in for fe_server, for FMU and client tests: it speaks
// the server side of the protocol on an ephemeral loopback port in a thread
// and can be told to misbehave.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "config/port_table.hpp"
#include "socketlib/protocol.h"

namespace testing_support {

// The tests' session token: $PCS_TOKEN, which CTest sets for every test
// (tests/CMakeLists.txt), so that fe_server children and in-process FMUs,
// which read it too, agree with the peers and handshakes made here.
std::string session_token();

class TestPeer {
 public:
  enum class Behaviour {
    Echo,           // RESULT values[i] = 2 * (sum of inputs) + i
    StallOnStep,    // accept STEP but never answer
    CloseMidFrame,  // answer STEP with half a header, then close
    WrongStep,      // answer STEP k with RESULT k + 1
    BadMagic,       // answer STEP with a frame of another protocol family
    NanResult,      // answer STEP with a NaN value
    OversizeResult, // answer STEP with a length field of 4 GiB
    OtherVersion,   // answer HELLO with a HELLO_ACK of protocol version 99
    OtherTable,     // answer HELLO with a HELLO_ACK for another port table
    Heartbeats,     // send three HEARTBEATs, 0.2 s apart, before each RESULT
    AcceptAnyProof, // an impostor: take any AUTH, answer with a HELLO_ACK proof of its own token
    SilentAfterHello, // read HELLO, then send nothing (a handshake that never ends)
    EndlessHeartbeats, // answer STEP with a HEARTBEAT every 0.1 s and never a RESULT
    Busy,           // answer HELLO with ABORT SL_EBUSY (a server in another session), then close
    CrowdedOnce,    // answer the first HELLO with ABORT SL_ECROWDED (a flood made room), then serve as Echo
    ClosedOnce,     // close after the first HELLO without a word (that ABORT lost), then serve as Echo
  };
  TestPeer(const config::PortTable& table, Behaviour b = Behaviour::Echo, std::string token = session_token());
  ~TestPeer();
  int port() const { return port_; }
  // Steps answered so far and the last error the peer saw (empty if none).
  int steps() const { return steps_; }
  // Connections dropped after their HELLO (CrowdedOnce, ClosedOnce).
  int crowded() const { return crowded_; }
  std::string error() const;
  void join();

 private:
  void serve();
  const config::PortTable& table_;
  Behaviour behaviour_;
  std::string token_;
  sl_socket listener_ = SL_SOCKET_INIT;
  int port_ = 0;
  std::atomic<int> steps_{0};
  std::atomic<int> crowded_{0};
  std::string error_;
  std::thread thread_;
};

// The client's side of the handshake by hand on a connected socket, with
// a chosen header version: "" when the server answered HELLO_ACK, else what
// went wrong ("ABORT: <reason>" when the server refused). With check_server
// false it sends its AUTH whatever the server's proof, as a stranger would.
std::string raw_client_handshake(sl_socket& s, const config::PortTable& t, const std::string& token = session_token(),
                                 uint16_t header_version = PCS_PROTOCOL_VERSION, bool check_server = true);

}  // namespace testing_support
