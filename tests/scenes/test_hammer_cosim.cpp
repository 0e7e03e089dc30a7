// The hammer co-simulated (piston in fe_server, the rest in tlm_host) against
// the monolithic reference over the first 20 ms of start-up, in both
// coupling modes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "h5io/timeseries.hpp"
#include "model.hpp"
#include "process.hpp"

using testing_support::ChildProcess;
using testing_support::TempDir;

namespace {

const std::string kSource = PCS_SCENES_DIR "/hammer_cosim";
const std::string kBuilt = PCS_BUILD_SCENES_DIR "/hammer_cosim";
constexpr double kStop = 0.02;

// Piston lift of the co-simulation: fe_server + tlm_host on loopback.
std::vector<double> cosim_lift(const TempDir& dir, const std::string& ports, const std::string& fmu,
                               std::vector<double>& t) {
  ChildProcess server({PCS_FE_SERVER_EXE, "--model", kBuilt + "/deck.k", "--ports", ports, "--listen",
                       "127.0.0.1:0", "--port-file", dir.file("port"), "--out", dir.file("fe.h5"), "--quiet",
                       "--accept-timeout", "20"});
  const int port = testing_support::read_port_file(dir.file("port"), 10.0);
  EXPECT_GT(port, 0) << server.output();
  ChildProcess host({PCS_TLM_HOST_EXE, kSource + "/model.tlm", "--fmu", fmu, "--server",
                     "127.0.0.1:" + std::to_string(port), "--out", dir.file("host.h5"), "--quiet", "--set",
                     "simulation.stoptime=" + std::to_string(kStop)});
  // Exit 4 is the report's complaint that 20 ms hold no settled blows; the run itself completed.
  const int rc = host.wait(200.0);
  EXPECT_TRUE(rc == 0 || rc == 4) << host.output();
  EXPECT_EQ(server.wait(30.0), 0) << server.output();
  t = h5io::read_series(dir.file("host.h5"), "time");
  return h5io::read_series(dir.file("host.h5"), "components/mech/x");
}

}  // namespace

TEST(HammerCosim, FollowsTheMonolithicReferenceInBothCouplingModes) {
  TempDir ref;
  tlm::ModelSpec spec = tlm::read_model(PCS_SCENES_DIR "/hammer_monolithic/model.tlm");
  spec.apply_override("simulation.stoptime=" + std::to_string(kStop));
  spec.report.clear();
  tlm::System mono(std::move(spec));
  mono.run(ref.file("mono.h5"), false);
  const auto tm = h5io::read_series(ref.file("mono.h5"), "time");
  const auto xm = h5io::read_series(ref.file("mono.h5"), "components/piston/x");
  const double lift = *std::max_element(xm.begin(), xm.end());
  ASSERT_GT(lift, 0.005) << "the reference piston must be moving by 20 ms";
  struct Mode {
    const char* name;
    std::string ports, fmu;
  };
  for (const Mode& mode : {Mode{"pressure", kSource + "/ports.cfg", kBuilt + "/hammer_cosim.fmu"},
                           Mode{"tlm", kSource + "/ports_tlm.cfg", kBuilt + "/hammer_cosim_tlm.fmu"}}) {
    TempDir dir;
    std::vector<double> tc;
    const auto xc = cosim_lift(dir, mode.ports, mode.fmu, tc);
    ASSERT_EQ(tc.size(), tm.size()) << mode.name;
    double worst = 0.0;
    for (size_t i = 0; i < tm.size(); ++i) worst = std::max(worst, std::fabs(xc[i] - xm[i]));
    // Sources of difference: the meshed collar faces are 0.5 % smaller than
    // the reference's areas (force and flow 0.5 % low, so up to ~0.5 % of the
    // lift), and the coupling's one-step delay (a shift of Δt = 1 µs, i.e.
    // v·Δt ≈ 5 µm). Bound: 1 % of the lift plus 50 µm.
    EXPECT_LT(worst, 0.01 * lift + 50e-6) << mode.name << " mode: worst |Δx| " << worst << " m of a " << lift << " m lift";
  }
}
