// The generated FMU at the C boundary: loaded from its .fmu by tlm_host's
// importer, called through the raw fmi2 functions against an in-process
// test peer.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include <chrono>
#include <cstdarg>
#include <memory>
#include <string>
#include <vector>

#include "config/port_table.hpp"
#include "fmi2/fmi2.h"
#include "fmu_importer.hpp"
#include "process.hpp"
#include "test_peer.hpp"

using testing_support::TestPeer;

namespace {

struct Log {
  std::vector<std::string> messages;
  std::string all() const {
    std::string s;
    for (const auto& m : messages) s += m + "\n";
    return s;
  }
};

extern "C" void capture(fmi2ComponentEnvironment env, fmi2String, fmi2Status, fmi2String, fmi2String fmt, ...) {
  char buf[2048];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  static_cast<Log*>(env)->messages.push_back(buf);
}

// The FMU's functions, looked up by name in its library.
struct Api {
#define MEMBER(name) name##TYPE* name;
  PCS_FMI2_FUNCTIONS(MEMBER)
#undef MEMBER
  explicit Api(void* lib) {
#define LOAD(name) name = reinterpret_cast<name##TYPE*>(dlsym(lib, #name));
    PCS_FMI2_FUNCTIONS(LOAD)
#undef LOAD
  }
};

class FmuTest : public ::testing::Test {
 protected:
  void SetUp() override {
    archive = std::make_shared<tlm::FmuArchive>(PCS_ONE_DOF_FMU);
    api = std::make_unique<Api>(archive->library());
    table = config::read_port_table(archive->dir() + "/resources/ports.cfg");
  }
  fmi2Component instantiate(const std::string& name, Log& log, const std::string& guid = "") {
    callbacks.push_back(std::make_unique<fmi2CallbackFunctions>(
        fmi2CallbackFunctions{capture, std::calloc, std::free, nullptr, &log}));
    return api->fmi2Instantiate(name.c_str(), fmi2CoSimulation,
                                guid.empty() ? archive->description().guid.c_str() : guid.c_str(),
                                archive->resource_uri().c_str(), callbacks.back().get(), fmi2False, fmi2False);
  }
  void point_at(fmi2Component c, int port, double timeout = 5.0) {
    fmi2ValueReference vr_host = config::kVrServerHost, vr_port = config::kVrServerPort, vr_to = config::kVrTimeout;
    fmi2String host = "127.0.0.1";
    ASSERT_EQ(api->fmi2SetString(c, &vr_host, 1, &host), fmi2OK);
    ASSERT_EQ(api->fmi2SetInteger(c, &vr_port, 1, &port), fmi2OK);
    ASSERT_EQ(api->fmi2SetReal(c, &vr_to, 1, &timeout), fmi2OK);
  }
  std::shared_ptr<tlm::FmuArchive> archive;
  std::unique_ptr<Api> api;
  config::PortTable table;
  std::vector<std::unique_ptr<fmi2CallbackFunctions>> callbacks;
};

}  // namespace

TEST_F(FmuTest, ExportsTheStandardFunctionsAndItsCheckpointFunctionsOnly) {
  void* lib = archive->library();
#define CHECK_EXPORTED(name) EXPECT_NE(dlsym(lib, #name), nullptr) << #name;
  PCS_FMI2_FUNCTIONS(CHECK_EXPORTED)
#undef CHECK_EXPORTED
  for (const char* ours : {"pcs_fmu_checkpoint", "pcs_fmu_resume", "pcs_fmu_confirm_resume", "pcs_fmu_stop_requested",
                           "pcs_fmu_set_stop_flag"})
    EXPECT_NE(dlsym(lib, ours), nullptr) << ours;
  // Our own code and the static libraries inside stay hidden.
  EXPECT_EQ(dlsym(lib, "sl_connect"), nullptr);
  EXPECT_EQ(dlsym(lib, "pcs_send_frame"), nullptr);
  EXPECT_STREQ(api->fmi2GetVersion(), "2.0");
  EXPECT_STREQ(api->fmi2GetTypesPlatform(), "default");
}

TEST_F(FmuTest, RefusesAWrongGuidOrModelExchange) {
  Log log;
  EXPECT_EQ(instantiate("bad", log, "pcs-0000000000000000"), nullptr);
  EXPECT_NE(log.all().find("GUID"), std::string::npos) << log.all();
  fmi2CallbackFunctions cb{capture, std::calloc, std::free, nullptr, &log};
  EXPECT_EQ(api->fmi2Instantiate("me", fmi2ModelExchange, archive->description().guid.c_str(),
                                 archive->resource_uri().c_str(), &cb, fmi2False, fmi2False),
            nullptr);
  EXPECT_EQ(api->fmi2Instantiate("nores", fmi2CoSimulation, archive->description().guid.c_str(),
                                 "http://example/resources", &cb, fmi2False, fmi2False),
            nullptr);
  EXPECT_NE(log.all().find("not a file: URI"), std::string::npos) << log.all();
}

TEST_F(FmuTest, OutOfSequenceCallsAreRefusedWithTheirName) {
  Log log;
  fmi2Component c = instantiate("seq", log);
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(api->fmi2DoStep(c, 0.0, table.dt, fmi2True), fmi2Error);
  EXPECT_NE(log.all().find("fmi2DoStep is not allowed in state instantiated"), std::string::npos) << log.all();
  EXPECT_EQ(api->fmi2ExitInitializationMode(c), fmi2Error);
  EXPECT_EQ(api->fmi2Terminate(c), fmi2Error);
  fmi2FMUstate s = nullptr;
  EXPECT_EQ(api->fmi2GetFMUstate(c, &s), fmi2Error);
  EXPECT_NE(log.all().find("canGetAndSetFMUstate"), std::string::npos);
  api->fmi2FreeInstance(c);
}

TEST_F(FmuTest, StepsAgainstAPeerWithScalingAndTwoInstances) {
  TestPeer peer1(table), peer2(table);
  Log log1, log2;
  fmi2Component a = instantiate("a", log1), b = instantiate("b", log2);
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  point_at(a, peer1.port());
  point_at(b, peer2.port());
  for (fmi2Component c : {a, b}) {
    ASSERT_EQ(api->fmi2SetupExperiment(c, fmi2False, 0, 0, fmi2False, 0), fmi2OK);
    ASSERT_EQ(api->fmi2EnterInitializationMode(c), fmi2OK);
    ASSERT_EQ(api->fmi2ExitInitializationMode(c), fmi2OK) << log1.all() << log2.all();
  }
  // cavity.p (vr 0) in; cavity.q (vr 1), cavity.x (vr 2) out. The peer answers 2·Σin + i.
  for (int k = 0; k < 3; ++k) {
    fmi2ValueReference in = 0, out[2] = {1, 2};
    double pa = 100.0 + k, pb = 7.0;
    ASSERT_EQ(api->fmi2SetReal(a, &in, 1, &pa), fmi2OK);
    ASSERT_EQ(api->fmi2SetReal(b, &in, 1, &pb), fmi2OK);
    ASSERT_EQ(api->fmi2DoStep(a, k * table.dt, table.dt, fmi2True), fmi2OK) << log1.all();
    ASSERT_EQ(api->fmi2DoStep(b, k * table.dt, table.dt, fmi2True), fmi2OK) << log2.all();
    double ya[2], yb[2];
    ASSERT_EQ(api->fmi2GetReal(a, out, 2, ya), fmi2OK);
    ASSERT_EQ(api->fmi2GetReal(b, out, 2, yb), fmi2OK);
    EXPECT_DOUBLE_EQ(ya[0], 2.0 * pa * table.to_fe[0].scale * table.to_host[0].scale);
    EXPECT_DOUBLE_EQ(ya[1], (2.0 * pa + 1.0) * table.to_host[1].scale);
    EXPECT_DOUBLE_EQ(yb[0], 2.0 * pb);
  }
  double last = 0;
  EXPECT_EQ(api->fmi2GetRealStatus(a, fmi2LastSuccessfulTime, &last), fmi2OK);
  EXPECT_DOUBLE_EQ(last, 3 * table.dt);
  for (fmi2Component c : {a, b}) {
    EXPECT_EQ(api->fmi2Terminate(c), fmi2OK);
    api->fmi2FreeInstance(c);
  }
  peer1.join();
  peer2.join();
  EXPECT_EQ(peer1.steps(), 3);
  EXPECT_EQ(peer2.steps(), 3);
}

// A communication step of n coupling steps is n exchanges with the inputs
// held (how FMPy steps by default: 2^k times the DefaultExperiment's
// stepSize); a step that is no whole multiple is refused with the nearest
// valid ones, never run out of step with fe_server.
TEST_F(FmuTest, ACommunicationStepOfSeveralCouplingStepsRunsThemAll) {
  TestPeer peer(table);
  Log log;
  fmi2Component c = instantiate("multi", log);
  point_at(c, peer.port());
  ASSERT_EQ(api->fmi2EnterInitializationMode(c), fmi2OK);
  ASSERT_EQ(api->fmi2ExitInitializationMode(c), fmi2OK);
  fmi2ValueReference in = 0, out = 1;
  const double p = 50.0;
  ASSERT_EQ(api->fmi2SetReal(c, &in, 1, &p), fmi2OK);
  ASSERT_EQ(api->fmi2DoStep(c, 0.0, 4 * table.dt, fmi2True), fmi2OK) << log.all();
  ASSERT_EQ(api->fmi2DoStep(c, 4 * table.dt, table.dt, fmi2True), fmi2OK) << log.all();
  double y = 0.0, last = 0.0;
  ASSERT_EQ(api->fmi2GetReal(c, &out, 1, &y), fmi2OK);
  EXPECT_DOUBLE_EQ(y, 2.0 * p * table.to_fe[0].scale * table.to_host[0].scale) << "the held input, echoed";
  EXPECT_EQ(api->fmi2GetRealStatus(c, fmi2LastSuccessfulTime, &last), fmi2OK);
  EXPECT_DOUBLE_EQ(last, 5 * table.dt);
  // 2.5 coupling steps: refused, with the two nearest valid steps.
  EXPECT_EQ(api->fmi2DoStep(c, 5 * table.dt, 2.5 * table.dt, fmi2True), fmi2Error);
  char want[160];
  std::snprintf(want, sizeof want, "is not a whole multiple of the coupling step %g s", table.dt);
  EXPECT_NE(log.all().find(want), std::string::npos) << log.all();
  std::snprintf(want, sizeof want, "use %g s or %g s", 2 * table.dt, 3 * table.dt);
  EXPECT_NE(log.all().find(want), std::string::npos) << log.all();
  api->fmi2FreeInstance(c);
  peer.join();
  EXPECT_EQ(peer.steps(), 5) << "four coupling steps in the first fmi2DoStep, one in the second";
}

TEST_F(FmuTest, NoServerFailsWithinTheDeadlineNeverHangs) {
  sl_socket probe = SL_SOCKET_INIT;  // bind and close: a port nobody listens on
  ASSERT_EQ(sl_listen("127.0.0.1", 0, &probe), SL_OK);
  int port = sl_local_port(&probe);
  sl_close(&probe);
  Log log;
  fmi2Component c = instantiate("noserver", log);
  point_at(c, port, 0.3);
  ASSERT_EQ(api->fmi2EnterInitializationMode(c), fmi2OK);
  auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(api->fmi2ExitInitializationMode(c), fmi2Error);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  EXPECT_NE(log.all().find("cannot connect"), std::string::npos) << log.all();
  EXPECT_NE(log.all().find("SL_EREFUSED"), std::string::npos) << log.all();
  api->fmi2FreeInstance(c);
}

TEST_F(FmuTest, StalledPeerTimesOutAndClosedPeerIsNamed) {
  for (auto behaviour : {TestPeer::Behaviour::StallOnStep, TestPeer::Behaviour::CloseMidFrame,
                         TestPeer::Behaviour::WrongStep}) {
    TestPeer peer(table, behaviour);
    Log log;
    fmi2Component c = instantiate("fault", log);
    point_at(c, peer.port(), 0.5);
    ASSERT_EQ(api->fmi2EnterInitializationMode(c), fmi2OK);
    ASSERT_EQ(api->fmi2ExitInitializationMode(c), fmi2OK);
    EXPECT_EQ(api->fmi2DoStep(c, 0.0, table.dt, fmi2True), fmi2Error);
    const std::string expected = behaviour == TestPeer::Behaviour::StallOnStep     ? "SL_ETIMEDOUT"
                                 : behaviour == TestPeer::Behaviour::CloseMidFrame ? "SL_ETRUNCATED"
                                                                                   : "expected RESULT 0";
    EXPECT_NE(log.all().find(expected), std::string::npos) << log.all();
    // After an error only reading, reset and freeing are allowed.
    EXPECT_EQ(api->fmi2DoStep(c, 0.0, table.dt, fmi2True), fmi2Error);
    api->fmi2FreeInstance(c);
  }
}

TEST_F(FmuTest, EveryFaultOfThePeerEndsTheStepWithItsCause) {
  struct Case {
    TestPeer::Behaviour behaviour;
    bool fails_in_handshake;
    const char* cause;
  };
  const Case cases[] = {
      {TestPeer::Behaviour::BadMagic, false, "SL_EBADMAGIC"},
      {TestPeer::Behaviour::NanResult, false, "is not finite"},
      {TestPeer::Behaviour::OversizeResult, false, "SL_EOVERSIZE"},
      {TestPeer::Behaviour::OtherVersion, true, "protocol version mismatch"},
      {TestPeer::Behaviour::OtherTable, true, "port table differs"},
  };
  for (const auto& c : cases) {
    TestPeer peer(table, c.behaviour);
    Log log;
    fmi2Component fmu = instantiate("fault", log);
    point_at(fmu, peer.port(), 2.0);
    ASSERT_EQ(api->fmi2EnterInitializationMode(fmu), fmi2OK);
    const auto t0 = std::chrono::steady_clock::now();
    if (c.fails_in_handshake) {
      EXPECT_EQ(api->fmi2ExitInitializationMode(fmu), fmi2Error) << c.cause;
    } else {
      ASSERT_EQ(api->fmi2ExitInitializationMode(fmu), fmi2OK) << log.all();
      EXPECT_EQ(api->fmi2DoStep(fmu, 0.0, table.dt, fmi2True), fmi2Error) << c.cause;
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.5) << "within the deadline";
    EXPECT_NE(log.all().find(c.cause), std::string::npos) << log.all();
    api->fmi2FreeInstance(fmu);
    peer.join();
    if (c.behaviour == TestPeer::Behaviour::BadMagic || c.behaviour == TestPeer::Behaviour::OversizeResult)
      EXPECT_EQ(peer.error().rfind(std::string("client sent ABORT: the host stops: "), 0), 0u)
          << "a garbage frame gets an ABORT with its cause, not a reset: " << peer.error();
  }
}

TEST_F(FmuTest, HeartbeatsKeepASlowStepAlive) {
  // The peer needs 0.6 s for the step but beats every 0.2 s; the deadline is 0.5 s.
  TestPeer peer(table, TestPeer::Behaviour::Heartbeats);
  Log log;
  fmi2Component fmu = instantiate("slow", log);
  point_at(fmu, peer.port(), 0.5);
  ASSERT_EQ(api->fmi2EnterInitializationMode(fmu), fmi2OK);
  ASSERT_EQ(api->fmi2ExitInitializationMode(fmu), fmi2OK);
  EXPECT_EQ(api->fmi2DoStep(fmu, 0.0, table.dt, fmi2True), fmi2OK) << log.all();
  api->fmi2FreeInstance(fmu);
}

// The Hopsan convention (host_convention, hopsan): every variable Hopsan's
// FMIWrapperQ reads for a NodeHydraulic port is there and means what Hopsan
// means: p = c + Zc·q (the node pressure a Q component gives, here with the
// flow the step returned; before the first step its start value,
// hopsan_start_pressure, which FMIWrapperQ reads from the model description
// and Hopsan logs at t = 0), T the oil's temperature, Qdot = 0 (isothermal).
// Exact: the same three operations as the host does.
TEST(FmuHopsan, EveryNodeHydraulicVariableIsThereAndMeansWhatHopsanMeans) {
  testing_support::TempDir dir;
  std::string cfg = config::read_text_file(PCS_SCENES_DIR "/one_dof_tlm/ports.cfg", "ports");
  cfg.replace(cfg.find("one_dof_tlm"), 11, "one_dof_hopsan");
  cfg.insert(cfg.find("$FMU_HOPSAN_PORTS"), "host_convention, hopsan\nhopsan_temperature, 313.0\nhopsan_start_pressure, 2.5e6\n");
  std::ofstream(dir.file("ports.cfg")) << cfg;
  testing_support::ChildProcess gen({PCS_FMUGEN_EXE, dir.file("ports.cfg"), "-o", dir.file("h.fmu")});
  ASSERT_EQ(gen.wait(30.0), 0) << gen.output();
  EXPECT_NE(gen.output().find("portspecs: NodeHydraulic:cavity,cavity.q,cavity.p,cavity.T,cavity.c,cavity.Zc,cavity.Qdot"),
            std::string::npos)
      << gen.output();
  auto archive = std::make_shared<tlm::FmuArchive>(dir.file("h.fmu"));
  const config::PortTable table = config::read_port_table(archive->dir() + "/resources/ports.cfg");
  TestPeer peer(table);
  {
    tlm::FmuInstance fmu(archive, "hopsan", false);
    fmu.set_string(fmu.vr("server.host"), "127.0.0.1");
    fmu.set_integer(fmu.vr("server.port"), peer.port());
    fmu.setup_experiment(0.0, 0.0);
    fmu.enter_initialization();
    const unsigned c = fmu.vr("cavity.c"), zc = fmu.vr("cavity.Zc"), q = fmu.vr("cavity.q"), p = fmu.vr("cavity.p");
    fmu.set_real(c, 2.0e6);
    fmu.set_real(zc, 3.0e9);
    fmu.exit_initialization();
    EXPECT_EQ(fmu.get_real(q), 0.0) << "its start value";
    EXPECT_EQ(fmu.get_real(p), 2.5e6) << "its start value before the first step";
    const std::string xml = config::read_text_file(archive->dir() + "/modelDescription.xml", "model description");
    const size_t at = xml.find("name=\"cavity.p\"");
    ASSERT_NE(at, std::string::npos);
    const std::string element = xml.substr(at, xml.find("</ScalarVariable>", at) - at);
    EXPECT_NE(element.find("initial=\"exact\""), std::string::npos) << element;
    EXPECT_NE(element.find("start=\"2500000\""), std::string::npos) << "the start value Hopsan reads: " << element;
    EXPECT_EQ(fmu.get_real(fmu.vr("cavity.T")), 313.0);
    EXPECT_EQ(fmu.get_real(fmu.vr("cavity.Qdot")), 0.0);
    fmu.do_step(0.0, table.dt);
    const double flow = fmu.get_real(q);
    EXPECT_EQ(flow, 2.0 * (2.0e6 + 3.0e9)) << "the peer's echo";
    EXPECT_EQ(fmu.get_real(p), 2.0e6 + 3.0e9 * flow);
    fmu.terminate();
  }
  peer.join();
  // Pressure coupling has no c and Zc to give Hopsan: refused, with its line.
  std::string pressure = cfg;
  pressure.replace(pressure.find("tlm", pressure.find("\nmode,")), 3, "pressure");
  pressure.replace(pressure.find("1,         wave"), pressure.find("$FMU_HOPSAN_RECEIVE") - pressure.find("1,         wave"),
                   "1, pressure, 1.0\n");
  try {
    config::parse_port_table(pressure, "p.cfg");
    ADD_FAILURE() << "a pressure-mode Hopsan table was accepted";
  } catch (const config::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("host_convention hopsan needs mode tlm"), std::string::npos) << e.what();
  }
}

// An importer that ends the run before the stop time it announced (FMPy and
// fmusim stepping at their own interval stopped at 0.99968 s of a 1 s run,
// in silence) is told at fmi2Terminate, with both times, as a warning; one
// that reaches it, or announced none, is not.
TEST_F(FmuTest, TerminatingBeforeTheAnnouncedStopTimeIsWarned) {
  struct Case {
    bool defined;
    int steps_announced, steps_run;
    bool warned;
  };
  for (const Case& c : {Case{true, 10, 7, true}, Case{true, 10, 10, false}, Case{false, 10, 7, false}}) {
    SCOPED_TRACE(std::to_string(c.steps_run) + " of " + std::to_string(c.steps_announced));
    TestPeer peer(table);
    Log log;
    fmi2Component fmu = instantiate("early", log);
    point_at(fmu, peer.port());
    ASSERT_EQ(api->fmi2SetupExperiment(fmu, fmi2False, 0, 0, c.defined ? fmi2True : fmi2False,
                                       c.steps_announced * table.dt),
              fmi2OK);
    ASSERT_EQ(api->fmi2EnterInitializationMode(fmu), fmi2OK);
    ASSERT_EQ(api->fmi2ExitInitializationMode(fmu), fmi2OK) << log.all();
    for (int k = 0; k < c.steps_run; ++k) ASSERT_EQ(api->fmi2DoStep(fmu, k * table.dt, table.dt, fmi2True), fmi2OK);
    EXPECT_EQ(api->fmi2Terminate(fmu), fmi2OK);
    api->fmi2FreeInstance(fmu);
    peer.join();
    const bool warned = log.all().find("before the stop time") != std::string::npos;
    EXPECT_EQ(warned, c.warned) << log.all();
    if (c.warned) EXPECT_NE(log.all().find("3 coupling steps early"), std::string::npos) << log.all();
  }
}

// FMI 2.0, fmi2Reset: "the same state as if fmi2Instantiate would have been
// called" - every variable at its start value, the server.* parameters too.
// Before, a reset kept the host, port, token and time-out that were set, so a
// second run silently went to the first run's server.
TEST_F(FmuTest, ResetReturnsEveryParameterToItsStartValueAndRunsAgain) {
  // The first run's server knows another token than $PCS_TOKEN; the second
  // run's knows $PCS_TOKEN only, so a token kept over the reset fails its handshake.
  const std::string first_token = "fedcba9876543210fedcba9876543210";
  TestPeer first(table, TestPeer::Behaviour::Echo, first_token), second(table);
  Log log;
  fmi2Component c = instantiate("reset", log);
  ASSERT_NE(c, nullptr);
  point_at(c, first.port(), 7.5);
  fmi2ValueReference vr_token = config::kVrServerToken;
  fmi2String token = first_token.c_str();
  ASSERT_EQ(api->fmi2SetString(c, &vr_token, 1, &token), fmi2OK);
  ASSERT_EQ(api->fmi2EnterInitializationMode(c), fmi2OK);
  ASSERT_EQ(api->fmi2ExitInitializationMode(c), fmi2OK) << log.all();
  fmi2ValueReference in = 0;
  double p = 3.0e6;
  ASSERT_EQ(api->fmi2SetReal(c, &in, 1, &p), fmi2OK);
  ASSERT_EQ(api->fmi2DoStep(c, 0.0, table.dt, fmi2True), fmi2OK) << log.all();
  ASSERT_EQ(api->fmi2Reset(c), fmi2OK) << log.all();
  // Values may be read from initialization mode on (FMI 2.0, 4.2.4).
  ASSERT_EQ(api->fmi2EnterInitializationMode(c), fmi2OK);
  fmi2ValueReference vr_host = config::kVrServerHost, vr_port = config::kVrServerPort, vr_to = config::kVrTimeout;
  fmi2String host = "x";
  fmi2Integer port = -1;
  fmi2Real timeout = -1, p_back = -1;
  ASSERT_EQ(api->fmi2GetString(c, &vr_host, 1, &host), fmi2OK);
  ASSERT_EQ(api->fmi2GetInteger(c, &vr_port, 1, &port), fmi2OK);
  ASSERT_EQ(api->fmi2GetReal(c, &vr_to, 1, &timeout), fmi2OK);
  ASSERT_EQ(api->fmi2GetReal(c, &in, 1, &p_back), fmi2OK);
  EXPECT_STREQ(host, "") << "server.host's start value is empty";
  EXPECT_EQ(port, 0) << "server.port's start value is 0";
  EXPECT_DOUBLE_EQ(timeout, table.timeout) << "server.timeout's start value is the table's";
  EXPECT_DOUBLE_EQ(p_back, 0.0) << "an input's start value is 0";
  // The instance runs again, as a new one would: pointed at a server anew,
  // with the token from the environment.
  point_at(c, second.port());
  ASSERT_EQ(api->fmi2ExitInitializationMode(c), fmi2OK) << log.all();
  ASSERT_EQ(api->fmi2DoStep(c, 0.0, table.dt, fmi2True), fmi2OK) << log.all();
  EXPECT_EQ(api->fmi2Terminate(c), fmi2OK);
  api->fmi2FreeInstance(c);
  first.join();
  second.join();
  EXPECT_EQ(first.steps(), 1);
  EXPECT_EQ(second.steps(), 1);
}

// The wait for a server that is not there is never silent: the start is
// logged (category logCoupling, shown with logging on), and every 5 s the
// importer's user is warned, with host, port and deadline.
TEST_F(FmuTest, AWaitForAServerSaysSoWhenItStartsAndEveryFiveSeconds) {
  sl_socket probe = SL_SOCKET_INIT;  // bind and close: a port nobody listens on
  ASSERT_EQ(sl_listen("127.0.0.1", 0, &probe), SL_OK);
  const int port = sl_local_port(&probe);
  sl_close(&probe);
  Log log;
  fmi2Component c = instantiate("waiting", log);
  ASSERT_EQ(api->fmi2SetDebugLogging(c, fmi2True, 0, nullptr), fmi2OK);
  point_at(c, port, 5.5);  // one 5 s note, then the deadline
  ASSERT_EQ(api->fmi2EnterInitializationMode(c), fmi2OK);
  EXPECT_EQ(api->fmi2ExitInitializationMode(c), fmi2Error);
  const std::string where = "fe_server at 127.0.0.1:" + std::to_string(port);
  EXPECT_NE(log.all().find("connecting to " + where + " (server.timeout: 5.5 s)"), std::string::npos) << log.all();
  EXPECT_NE(log.all().find("no answer from " + where), std::string::npos) << log.all();
  EXPECT_NE(log.all().find("retrying until 5.5 s have passed (5 s so far)"), std::string::npos) << log.all();
  EXPECT_NE(log.all().find("SL_EREFUSED"), std::string::npos) << "and at the end, why it failed\n" << log.all();
  api->fmi2FreeInstance(c);
}
