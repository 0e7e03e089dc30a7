// Hopsan model files (hopsan_loader.hpp): a circuit written in Hopsan's
// format runs exactly as the same circuit in ours (bit for bit: the same
// components from the same parameters), reaches the analytic steady state,
// and what the loader cannot read exactly is refused with its line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "config/keyword_reader.hpp"
#include "h5io/timeseries.hpp"
#include "hopsan_loader.hpp"
#include "model.hpp"
#include "process.hpp"

namespace {

const std::string kDir = PCS_SOURCE_DIR "/tests/tlm_host/hopsan";

std::string text_of(const std::string& path) {
  std::stringstream s;
  s << std::ifstream(path).rdbuf();
  return s.str();
}

// The loader's error for a variant of the model file, "" if it loads.
std::string error_of(const std::string& hmf) {
  testing_support::TempDir dir;
  std::ofstream(dir.file("m.hmf")) << hmf;
  try {
    tlm::read_hmf(dir.file("m.hmf"));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  if (at == std::string::npos) return "";
  return s.replace(at, from.size(), to);
}

}  // namespace

TEST(HopsanLoader, AHopsanModelRunsAsItsTwinInOurFormatAndReachesTheSteadyState) {
  testing_support::TempDir dir;
  tlm::HmfModel hmf = tlm::read_hmf(kDir + "/orifice_volume.hmf");
  ASSERT_EQ(hmf.spec.components.size(), 5u) << "the sensor only taps a node";
  ASSERT_EQ(hmf.notes.size(), 2u);
  EXPECT_NE(hmf.notes[0].find("orifice_volume.hmf:36: chamber (HydraulicVolume → HydraulicVolumeC): its oil is conserved"),
            std::string::npos)
      << hmf.notes[0];
  EXPECT_NE(hmf.notes[1].find("gauge: a Hopsan sensor"), std::string::npos) << hmf.notes[1];
  tlm::System(std::move(hmf.spec)).run(dir.file("hmf.h5"), false);
  tlm::System(tlm::read_model(kDir + "/orifice_volume.tlm")).run(dir.file("tlm.h5"), false);
  const auto series = h5io::list_series(dir.file("tlm.h5"));
  ASSERT_GT(series.size(), 10u);
  for (const auto& [name, rows] : series) {
    const auto a = h5io::read_series(dir.file("hmf.h5"), name), b = h5io::read_series(dir.file("tlm.h5"), name);
    ASSERT_EQ(a.size(), b.size()) << name << ": logsamples 1000 of 5000 steps is log_every 5";
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << name;
  }
  // Steady state: the turbulent inflow C_q·A·√(2(p_s − p)/ρ) equals the
  // laminar outflow K_c·(p − p_t). The volume's time constant V/(β·dq/dp),
  // about 0.3 ms, is far below the 50 ms run: within 1e-4 of the root.
  auto imbalance = [](double p) { return 0.67e-6 * std::sqrt(2 * (1e7 - p) / 870) - 1e-11 * (p - 1e5); };
  double lo = 1e5, hi = 1e7;
  for (int i = 0; i < 200; ++i) (imbalance(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
  const double p = h5io::read_series(dir.file("hmf.h5"), "nodes/chamber.P2/p").back();
  EXPECT_NEAR(p, lo, 1e-4 * lo);
}

TEST(HopsanLoader, WhatItCannotReadExactlyIsRefusedWithItsLine) {
  const std::string hmf = text_of(kDir + "/orifice_volume.hmf");
  ASSERT_EQ(error_of(hmf), "");
  std::string e = error_of(replaced(hmf, "typename=\"HydraulicLaminarOrifice\"", "typename=\"Hydraulic43Valve\""));
  EXPECT_NE(e.find("m.hmf:52: component 'drain' of Hopsan type Hydraulic43Valve has no counterpart here yet"),
            std::string::npos)
      << e;
  e = error_of(replaced(hmf, "name=\"Beta_e\"/>", "name=\"Beta_e\"/>\n          <parameter value=\"1\" name=\"Foo\"/>"));
  EXPECT_NE(e.find("chamber (HydraulicVolume): parameter 'Foo' = '1' has no counterpart in HydraulicVolumeC"),
            std::string::npos)
      << e;
  e = error_of(replaced(hmf, "value=\"V0\"", "value=\"2*V0\""));
  EXPECT_NE(e.find("m.hmf:47: chamber (HydraulicVolume): parameter 'V' = '2*V0': a number or a system parameter's name"),
            std::string::npos)
      << e;
  e = error_of(replaced(hmf, "value=\"0\" type=\"double\" name=\"P2::Flow\"", "value=\"1e-4\" type=\"double\" name=\"P2::Flow\""));
  EXPECT_NE(e.find("parameter 'P2::Flow' = '1e-4'"), std::string::npos) << e << " (a start flow Hopsan would use)";
  e = error_of(replaced(hmf, "<component typename=\"HydraulicTankC\" name=\"tank\">",
                        "<system typename=\"Subsystem\" name=\"sub\"/>\n      <component typename=\"HydraulicTankC\" name=\"tank\">"));
  EXPECT_NE(e.find("'sub' (<system>): nested subsystems"), std::string::npos) << e;
  e = error_of(replaced(hmf, "endcomponent=\"tank\" endport=\"P1\"/>",
                        "endcomponent=\"tank\" endport=\"P1\"/>\n      <connect startcomponent=\"gauge\" startport=\"out\" "
                        "endcomponent=\"tank\" endport=\"p\"/>"));
  EXPECT_NE(e.find("sensor gauge: its signal 'out' is used"), std::string::npos) << e;
  e = error_of(replaced(hmf, "start=\"0\"", "start=\"0.1\""));
  EXPECT_NE(e.find("runs start at t = 0"), std::string::npos) << e;
  EXPECT_NE(error_of("<notxml").find("not a readable XML file"), std::string::npos);
}

// Hopsan's signal blocks feed a component: a step (0, then 1e-5 m³/s at
// 10 ms) times a gain of 2 drives a flow source into a shut 100 cm³ volume.
// Before the step nothing moves; after it the pressure rises at β·q/V =
// 2.8e8 Pa/s. Tolerance: one step's worth of that rise (the step's value
// holds from the end of the step it falls in, as in Hopsan) and the seal's
// leak (Kc = 1e-16: 3e-10 m³/s at 29 bar, 1e-5 of the flow).
TEST(HopsanLoader, SignalsDriveAFlowSourceIntoAVolume) {
  testing_support::TempDir dir;
  tlm::HmfModel hmf = tlm::read_hmf(kDir + "/step_flow.hmf");
  const double dt = hmf.spec.dt;
  tlm::System(std::move(hmf.spec)).run(dir.file("sf.h5"), false);
  const auto t = h5io::read_series(dir.file("sf.h5"), "time");
  const auto p = h5io::read_series(dir.file("sf.h5"), "nodes/chamber.P1/p");
  const double rate = 1.4e9 * 2e-5 / 1e-4;
  for (size_t i = 0; i < t.size(); ++i) {
    const double expect = 1e5 + rate * std::max(0.0, t[i] - 0.01);
    EXPECT_NEAR(p[i], expect, 1.01 * rate * dt) << "t = " << t[i];
  }
  EXPECT_GT(p.back(), 2.8e6) << "the pump ran";
}
