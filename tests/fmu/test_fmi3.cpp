// The FMU's FMI 3.0 interface (issue 38): the same binary, link and state
// machine as FMI 2.0's, behind 3.0's functions, against an in-process peer.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "config/port_table.hpp"
#include "fmi3/fmi3.h"
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

extern "C" void capture3(fmi3InstanceEnvironment env, fmi3Status, fmi3String, fmi3String message) {
  static_cast<Log*>(env)->messages.push_back(message);
}

// The functions, looked up by name in the module as an importer does.
struct Api3 {
#define MEMBER(name) decltype(&::name) name;
  PCS_FMI3_FUNCTIONS(MEMBER)
#undef MEMBER
  explicit Api3(void* lib) {
#define LOAD(name) name = reinterpret_cast<decltype(&::name)>(dlsym(lib, #name));
    PCS_FMI3_FUNCTIONS(LOAD)
#undef LOAD
  }
};

class Fmi3Test : public ::testing::Test {
 protected:
  void SetUp() override {
    lib = dlopen(PCS_FMU_MODULE, RTLD_NOW | RTLD_LOCAL);
    ASSERT_NE(lib, nullptr) << dlerror();
    api = std::make_unique<Api3>(lib);
    table = config::read_port_table(resources + "ports.cfg");
  }
  void TearDown() override {
    if (lib) dlclose(lib);
  }
  fmi3Instance instantiate(const std::string& name, Log& log, const std::string& token, bool event_mode = false) {
    return api->fmi3InstantiateCoSimulation(name.c_str(), token.c_str(), resources.c_str(), false, false, event_mode,
                                            false, nullptr, 0, &log, capture3, nullptr);
  }
  void* lib = nullptr;
  std::unique_ptr<Api3> api;
  const std::string resources = std::string(PCS_SCENES_DIR) + "/one_dof/";  // 3.0: a path, with a trailing separator
  config::PortTable table;
};

}  // namespace

TEST_F(Fmi3Test, EveryFunctionOfTheStandardIsExported) {
#define CHECK_EXPORTED(name) EXPECT_NE(dlsym(lib, #name), nullptr) << #name;
  PCS_FMI3_FUNCTIONS(CHECK_EXPORTED)
#undef CHECK_EXPORTED
  EXPECT_STREQ(api->fmi3GetVersion(), "3.0");
  EXPECT_EQ(dlsym(lib, "sl_connect"), nullptr) << "our own code stays hidden";
}

TEST_F(Fmi3Test, AWrongTokenEventModeOrModelExchangeIsRefusedSayingWhy) {
  Log log;
  EXPECT_EQ(instantiate("bad", log, "pcs-0000000000000000"), nullptr);
  EXPECT_NE(log.all().find("does not match resources/ports.cfg"), std::string::npos) << log.all();
  EXPECT_EQ(instantiate("events", log, config::fmu_guid(table), true), nullptr);
  EXPECT_NE(log.all().find("hasEventMode is false"), std::string::npos) << log.all();
  EXPECT_EQ(api->fmi3InstantiateModelExchange("me", config::fmu_guid(table).c_str(), resources.c_str(), false, false,
                                              &log, capture3),
            nullptr);
  EXPECT_NE(log.all().find("co-simulation only"), std::string::npos) << log.all();
}

// cavity.p (vr 0) in; cavity.q (vr 1), cavity.x (vr 2) out; the peer answers
// 2·Σin + i, so each output says which input and step it came from.
TEST_F(Fmi3Test, StepsAgainstAPeerWithTimeFlagsAndOutputsAsFmi2Does) {
  TestPeer peer(table);
  Log log;
  fmi3Instance c = instantiate("three", log, config::fmu_guid(table));
  ASSERT_NE(c, nullptr) << log.all();
  const fmi3ValueReference vr_host = config::kVrServerHost, vr_port = config::kVrServerPort,
                           vr_to = config::kVrTimeout, vr_time = config::kVrTime;
  const fmi3String host = "127.0.0.1";
  const fmi3Int32 port = peer.port();
  const fmi3Float64 timeout = 5.0;
  ASSERT_EQ(api->fmi3SetString(c, &vr_host, 1, &host, 1), fmi3OK) << log.all();
  ASSERT_EQ(api->fmi3SetInt32(c, &vr_port, 1, &port, 1), fmi3OK) << log.all();
  ASSERT_EQ(api->fmi3SetFloat64(c, &vr_to, 1, &timeout, 1), fmi3OK) << log.all();
  ASSERT_EQ(api->fmi3EnterInitializationMode(c, false, 0.0, 0.0, true, 3 * table.dt), fmi3OK) << log.all();
  ASSERT_EQ(api->fmi3ExitInitializationMode(c), fmi3OK) << log.all();
  for (int k = 0; k < 3; ++k) {
    const fmi3ValueReference in = 0, out[2] = {1, 2};
    const fmi3Float64 p = 100.0 + k;
    ASSERT_EQ(api->fmi3SetFloat64(c, &in, 1, &p, 1), fmi3OK) << log.all();
    fmi3Boolean event = true, terminate = true, early = true;
    fmi3Float64 last = -1;
    ASSERT_EQ(api->fmi3DoStep(c, k * table.dt, table.dt, true, &event, &terminate, &early, &last), fmi3OK) << log.all();
    EXPECT_FALSE(event);
    EXPECT_FALSE(terminate);
    EXPECT_FALSE(early);
    EXPECT_DOUBLE_EQ(last, (k + 1) * table.dt);
    fmi3Float64 y[2] = {0, 0}, t = -1;
    ASSERT_EQ(api->fmi3GetFloat64(c, out, 2, y, 2), fmi3OK);
    ASSERT_EQ(api->fmi3GetFloat64(c, &vr_time, 1, &t, 1), fmi3OK);
    EXPECT_DOUBLE_EQ(y[0], 2.0 * p * table.to_fe[0].scale * table.to_host[0].scale);
    EXPECT_DOUBLE_EQ(y[1], (2.0 * p + 1.0) * table.to_host[1].scale);
    EXPECT_DOUBLE_EQ(t, (k + 1) * table.dt);
  }
  // Scalars only, and no variable of the other types.
  const fmi3ValueReference out = 1;
  fmi3Float64 two[2];
  EXPECT_EQ(api->fmi3GetFloat64(c, &out, 1, two, 2), fmi3Error);
  EXPECT_NE(log.all().find("2 values for 1 value references"), std::string::npos) << log.all();
  EXPECT_EQ(api->fmi3Terminate(c), fmi3Error) << "an error puts the instance in its error state";
  api->fmi3FreeInstance(c);
  peer.join();
  EXPECT_EQ(peer.steps(), 3);
}

TEST_F(Fmi3Test, WhatTheModelDescriptionSaysItCannotDoIsRefusedNamingTheCapability) {
  Log log;
  fmi3Instance c = instantiate("caps", log, config::fmu_guid(table));
  ASSERT_NE(c, nullptr) << log.all();
  fmi3FMUState s = nullptr;
  EXPECT_EQ(api->fmi3GetFMUState(c, &s), fmi3Error);
  EXPECT_NE(log.all().find("canGetAndSetFMUState is false"), std::string::npos) << log.all();
  fmi3Instance d = instantiate("caps2", log, config::fmu_guid(table));
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(api->fmi3EnterEventMode(d), fmi3Error);
  EXPECT_NE(log.all().find("hasEventMode is false"), std::string::npos) << log.all();
  fmi3Instance e = instantiate("caps3", log, config::fmu_guid(table));
  ASSERT_NE(e, nullptr);
  ASSERT_EQ(api->fmi3EnterInitializationMode(e, false, 0.0, 0.0, false, 0.0), fmi3OK);
  fmi3Boolean b[1];
  const fmi3ValueReference vr = 0;
  EXPECT_EQ(api->fmi3GetBoolean(e, &vr, 0, b, 0), fmi3OK) << "an empty call is fine";
  EXPECT_EQ(api->fmi3GetBoolean(e, &vr, 1, b, 1), fmi3Error);
  EXPECT_NE(log.all().find("no Boolean variables"), std::string::npos) << log.all();
  for (fmi3Instance i : {c, d, e}) api->fmi3FreeInstance(i);
}
