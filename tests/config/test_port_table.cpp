#include <gtest/gtest.h>

#include "config/port_table.hpp"

using config::InputError;
using config::parse_port_table;

namespace {
const char* kTable = R"($FMU_SETTINGS
model, demo
server, 127.0.0.1:5000
timestep, 1e-6
mode, pressure
$FMU_HOPSAN_PORTS
1, cavA, Hydraulic
2, piston, Mechanic
$FMU_HOPSAN_SEND
1, pressure, 1.0
2, force, 0.25
$FMU_HOPSAN_RECEIVE
1, flow, 4.0
1, x
2, velocity
)";

std::string error_of(const std::string& text) {
  try {
    parse_port_table(text, "ports.cfg");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(PortTable, ReadsSettingsPortsAndVariables) {
  auto t = parse_port_table(kTable, "ports.cfg");
  EXPECT_EQ(t.model_name, "demo");
  EXPECT_EQ(t.dt, 1e-6);
  ASSERT_EQ(t.ports.size(), 2u);
  EXPECT_EQ(t.ports[1].type, config::PortType::Mechanic);
  ASSERT_EQ(t.to_fe.size(), 2u);
  EXPECT_EQ(t.to_fe[1].name(), "piston.F");
  EXPECT_EQ(t.to_fe[1].scale, 0.25);
  ASSERT_EQ(t.to_host.size(), 3u);
  EXPECT_EQ(t.to_host[1].name(), "cavA.x");
  EXPECT_EQ(t.to_host[1].scale, 1.0);  // default scale
}

TEST(PortTable, HashChangesWithWhatTheSidesMustAgreeOn) {
  auto base = parse_port_table(kTable, "a.cfg");
  std::string t = kTable;
  auto scale = parse_port_table(std::string(t).replace(t.find("4.0"), 3, "2.0"), "b.cfg");
  auto dt = parse_port_table(std::string(t).replace(t.find("1e-6"), 4, "2e-6"), "c.cfg");
  auto server = parse_port_table(std::string(t).replace(t.find("5000"), 4, "6000"), "d.cfg");
  EXPECT_NE(base.hash(), scale.hash());
  EXPECT_NE(base.hash(), dt.hash());
  EXPECT_EQ(base.hash(), server.hash()) << "the server address may differ between cluster and workstation";
  // The host's convention: pcs (the default, said or not) keeps every
  // existing table's hash and its FMUs' GUIDs; hopsan changes the FMU's variables, so the hash.
  const size_t settings_end = t.find("$FMU_HOPSAN_PORTS");
  auto pcs = parse_port_table(std::string(t).insert(settings_end, "host_convention, pcs\n"), "e.cfg");
  EXPECT_EQ(base.hash(), pcs.hash());
  EXPECT_NE(error_of(std::string(t).insert(settings_end, "host_convention, hopsan\n")).find("needs mode tlm"),
            std::string::npos);
  const std::string tlm = config::read_text_file(PCS_SCENES_DIR "/one_dof_tlm/ports.cfg", "ports");
  const size_t at = tlm.find("$FMU_HOPSAN_PORTS");
  EXPECT_NE(parse_port_table(tlm, "g.cfg").hash(),
            parse_port_table(std::string(tlm).insert(at, "host_convention, hopsan\n"), "h.cfg").hash());
}

TEST(PortTable, ErrorsSayWhatAndWhere) {
  std::string t = kTable;
  EXPECT_NE(error_of(std::string(t).replace(t.find("Mechanic"), 8, "Electric")).find("ports.cfg:8: port type 'Electric'"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(t) + "3, flow\n").find("ports.cfg:16: port id 3 is not listed"), std::string::npos);
  EXPECT_NE(error_of(std::string(t) + "1, flow\n").find("is already listed"), std::string::npos);
  EXPECT_NE(error_of(std::string(t) + "1, pressure\n").find("cannot send and receive the same quantity"), std::string::npos);
  EXPECT_NE(error_of(std::string(t).replace(t.find("1, pressure, 1.0"), 16, "1, force, 1.0")).find("cannot send force"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(t).replace(t.find("mode, pressure"), 14, "mode, tlm")).find("must send wave and impedance"),
            std::string::npos);
  EXPECT_NE(error_of("$FMU_SETTINGS\nmodel, a b\ntimestep, 1\n").find("model name"), std::string::npos);
  EXPECT_NE(error_of("$FMU_NONSENSE\n").find("unknown block"), std::string::npos);
}

TEST(PortTable, FmuVariablesDeriveFromTheTable) {
  auto t = parse_port_table(kTable, "ports.cfg");
  auto vars = config::fmu_variables(t);
  ASSERT_EQ(vars.size(), 2u + 3u + 4u);
  EXPECT_EQ(vars[0].name, "cavA.p");
  EXPECT_EQ(vars[0].causality, config::FmuCausality::Input);
  EXPECT_EQ(vars[2].name, "cavA.q");
  EXPECT_EQ(vars[2].causality, config::FmuCausality::Output);
  EXPECT_EQ(vars[2].value_reference, 2u);
  for (size_t i = 0; i < vars.size(); ++i)
    for (size_t j = i + 1; j < vars.size(); ++j) EXPECT_NE(vars[i].value_reference, vars[j].value_reference);
  EXPECT_EQ(config::fmu_guid(t).size(), 4u + 16u);
}

// A negative scale is refused at its line (pressure x -1 put the one-DOF
// piston 8.5 km away with exit 0): scales map a symmetric model's share to
// the whole and are positive.
TEST(PortTable, ANegativeScaleIsRefusedAtItsLine) {
  const std::string t = config::read_text_file(PCS_SCENES_DIR "/one_dof/ports.cfg", "ports");
  const std::string good = "1,         pressure, 1.0";
  ASSERT_NE(t.find(good), std::string::npos) << t;
  std::string bad = t;
  bad.replace(bad.find(good), good.size(), "1,         pressure, -1.0");
  EXPECT_NO_THROW(config::parse_port_table(t, "good.cfg"));
  try {
    config::parse_port_table(bad, "neg.cfg");
    FAIL() << "a negative scale must be refused:\n" << bad;
  } catch (const config::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("neg.cfg:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is negative"), std::string::npos) << e.what();
  }
}

// Pressure mode may send the host's impedance for fe_server's stability
// check (the port stays pressure-coupled: its FMU input says what it is for);
// a wave there would be half a TLM port in a pressure table and is refused.
TEST(PortTable, APressurePortMaySendItsImpedanceForTheCheckButNotAWave) {
  const std::string t = kTable;
  const std::string with_zc = std::string(t).replace(t.find("2, force, 0.25"), 14, "2, force, 0.25\n1, impedance");
  auto table = parse_port_table(with_zc, "ports.cfg");
  EXPECT_EQ(table.mode, config::CouplingMode::Pressure);
  bool described = false;
  for (const auto& v : config::fmu_variables(table))
    if (v.name == "cavA.Zc")
      described = v.causality == config::FmuCausality::Input &&
                  v.description.find("stability check of pressure coupling") != std::string::npos;
  EXPECT_TRUE(described) << "cavA.Zc is the FMU's input for the check";
  const std::string with_wave = std::string(t).replace(t.find("2, force, 0.25"), 14, "2, force, 0.25\n1, wave");
  EXPECT_NE(error_of(with_wave).find("ports.cfg:7: hydraulic port 'cavA' in pressure mode sends a wave"), std::string::npos)
      << error_of(with_wave);
}
