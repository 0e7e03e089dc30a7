// tlm_host: component equations against their physics, and the model reader.
#include <gtest/gtest.h>
#include <zip.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <type_traits>

#include "components/hydraulic/HydraulicTurbulentOrificeQ.hpp"
#include "components/rigid_body.hpp"
#include "fmu_importer.hpp"
#include "h5io/timeseries.hpp"
#include "model.hpp"
#include "process.hpp"

namespace {

std::string write_model(const testing_support::TempDir& dir, const std::string& text) {
  std::string path = dir.file("model.tlm");
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST(TurbulentOrifice, ExactSolutionSatisfiesTheOrificeEquation) {
  const double K = 0.65 * 1e-5 * std::sqrt(2.0 / 870.0);
  for (double Z : {0.0, 1e8, 1e11, 1e13}) {
    for (double dc : {-5e6, -1.0, 0.0, 3e5, 2e7}) {
      const double c1 = 1e7 + dc, c2 = 1e7, Zc1 = Z, Zc2 = 0.5 * Z;
      const double q = tlm::turbulent_orifice_flow(c1, c2, Zc1, Zc2, K);
      EXPECT_GE(q * dc, 0.0) << "flow must go from high to low pressure";
      // |q| = x solves x² + K²·Z·x − K²·D = 0 (D = |c1 − c2|, Z = Zc1 + Zc2).
      // Recomputing Δp from the ~1e7 Pa node pressures would cancel
      // catastrophically when Z·x ≈ D, so the root is checked on the quadratic:
      // its residual must be round-off of its largest term.
      const double x = std::fabs(q), D = std::fabs(c1 - c2), Zs = Zc1 + Zc2;
      const double terms[3] = {x * x, K * K * Zs * x, K * K * D};
      const double scale = std::max({terms[0], terms[1], terms[2]});
      EXPECT_LE(std::fabs(terms[0] + terms[1] - terms[2]), 1e-12 * scale) << "Z=" << Z << " dc=" << dc;
      if (Z == 0.0) {
        EXPECT_DOUBLE_EQ(x, K * std::sqrt(D)) << "stiff nodes: the plain orifice law";
      }
    }
  }
}

TEST(StableStep, AnExplicitStopWithADamperIsStableJustBelowItsLimitAndGrowsJustAbove) {
  // The components step stops as F = −k·x − c·v with v of the last step,
  // v⁺ = v + Δt·F/m, x⁺ = x + Δt·v⁺. ±2 % around the advertised limit must
  // separate decay from growth, for light to heavy damping (the spool's
  // stop is ζ = 0.79: its limit is 0.48 of the undamped 2/ω).
  const double k = 5e7, m = 0.2;
  for (double zeta : {0.3, 0.79, 2.0}) {
    const double c = 2.0 * zeta * std::sqrt(k * m);
    const double limit = tlm::spring_damper_stable_step(k, c, m);
    auto final_amplitude = [&](double dt) {
      double x = 1e-3, v = 0.0;
      for (int i = 0; i < 20000 && std::fabs(x) < 1.0; ++i) {
        v += dt * (-k * x - c * v) / m;
        x += dt * v;
      }
      return std::fabs(x);
    };
    EXPECT_LT(final_amplitude(0.98 * limit), 1e-3) << "ζ = " << zeta;
    EXPECT_GT(final_amplitude(1.02 * limit), 1e-3) << "ζ = " << zeta;
  }
}

TEST(HydraulicVolume, PressurisationRateIsBetaOverVTimesFlow) {
  // A 1 l volume fed through an orifice from 200 bar, starting at 10 bar.
  testing_support::TempDir dir;
  std::string path = write_model(dir, R"(*SIMULATION
timestep, 1e-6
stoptime, 2e-4
*COMPONENT
src, PressureSourceC, p=2.0e7
ori, HydraulicTurbulentOrificeQ, Cd=0.6, A=2e-6, rho=870
vol, HydraulicVolumeC, V=1e-3, beta=1.5e9, p0=1e6, ports=1
*CONNECT
src.P1, ori.P1
ori.P2, vol.P1
)");
  tlm::System sys(tlm::read_model(path));
  sys.run(dir.file("r.h5"), false);
  auto t = h5io::read_series(dir.file("r.h5"), "time");
  auto p = h5io::read_series(dir.file("r.h5"), "nodes/vol.P1/p");
  auto q = h5io::read_series(dir.file("r.h5"), "nodes/vol.P1/q");
  ASSERT_EQ(t.size(), 201u);
  // Over the run p rises by ~0.36 bar of 190: q is nearly constant, so the
  // mean rate is β/V·q to within the relative change of q (≈ 1e-3).
  const double rate = (p[200] - p[100]) / (t[200] - t[100]);
  const double expected = 1.5e9 / 1e-3 * 0.5 * (q[100] + q[200]);
  EXPECT_NEAR(rate, expected, 2e-3 * expected);
  // And the flow is the orifice's at that pressure difference.
  const double K = 0.6 * 2e-6 * std::sqrt(2.0 / 870.0);
  EXPECT_NEAR(q[150], K * std::sqrt(2e7 - p[150]), 1e-6 * q[150]);
}

TEST(HydraulicVolume, ClosedCircuitConservesMass) {
  // Two volumes at different pressures joined by an orifice: the pressure
  // settles where β/V-weighted mass balance says, V1·p1 + V2·p2 conserved.
  testing_support::TempDir dir;
  std::string path = write_model(dir, R"(*SIMULATION
timestep, 1e-6
stoptime, 0.05
*COMPONENT
a, HydraulicVolumeC, V=1e-4, beta=1e9, p0=2e7, ports=1
b, HydraulicVolumeC, V=3e-4, beta=1e9, p0=1e5, ports=1
o, HydraulicTurbulentOrificeQ, Cd=0.7, A=1e-6
*CONNECT
a.P1, o.P1
o.P2, b.P1
)");
  tlm::System sys(tlm::read_model(path));
  sys.run(dir.file("r.h5"), false);
  auto pa = h5io::read_series(dir.file("r.h5"), "nodes/a.P1/p");
  auto pb = h5io::read_series(dir.file("r.h5"), "nodes/b.P1/p");
  const double before = 1e-4 * 2e7 + 3e-4 * 1e5, after = 1e-4 * pa.back() + 3e-4 * pb.back();
  // TLM volumes integrate flow exactly (it is summed, not approximated), so
  // the oil volume is conserved to round-off of the ~1e7 Pa pressures.
  EXPECT_NEAR(after, before, 1e-9 * before);
  EXPECT_NEAR(pa.back(), before / 4e-4, 0.01 * before / 4e-4) << "equalised at (1·20 + 3·0.1)/4 MPa";
}

TEST(ParameterSet, EveryParameterDeclaresItsUnitAndThePlausibleOnesAgreeWithTheTable) {
  // Only a string literal is a unit: a fallback of 0 (or a runtime text)
  // in its place does not compile.
  static_assert(!std::is_convertible_v<int, tlm::Unit>);
  static_assert(!std::is_convertible_v<const char*, tlm::Unit>);
  tlm::ParameterSet ps;
  ps.set("p0", "2e5", {"model.tlm", 3});
  EXPECT_THROW(ps.real("p0", 1e5, "bar"), std::logic_error) << "p0 is a pressure: the table's unit is Pa";
  EXPECT_EQ(ps.real("p0", 1e5, "Pa"), 2e5);
  // Every registered type, configured with nothing given: whatever it reads
  // before a required parameter stops it declares a unit the table accepts
  // (a std::logic_error otherwise; InputError is a runtime_error).
  size_t checked = 0;
  for (const auto& [type, make] : tlm::component_types()) {
    auto c = make("c");
    tlm::ParameterSet none;
    try {
      c->configure(none);
    } catch (const config::InputError&) {
    } catch (const std::logic_error& e) {
      ADD_FAILURE() << type << ": " << e.what();
    } catch (const std::exception&) {
    }
    ++checked;
  }
  EXPECT_GT(checked, 30u);
}

TEST(ModelReader, ErrorsNameTheLineAndTheFix) {
  testing_support::TempDir dir;
  auto error_of = [&](const std::string& text) -> std::string {
    try {
      tlm::System sys(tlm::read_model(write_model(dir, text)));
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  };
  const std::string head = "*SIMULATION\ntimestep, 1e-6\nstoptime, 1e-3\n*COMPONENT\n";
  std::string e = error_of(head + "v, HydraulicVolumeC, V=1e-3, Vee=3\n");
  EXPECT_NE(e.find("model.tlm:5: component v has no parameter 'Vee'"), std::string::npos) << e;
  EXPECT_NE(e.find("its parameters: V [m³], V_min [m³], alpha [1], beta [Pa], dVdx [m²], p0 [Pa], p_vap [Pa], ports [1]"),
            std::string::npos)
      << "what the component reads, each with the unit it declares: " << e;
  e = error_of(head + "v, HydraulicVolumeC, bta=1.4e9\n");
  EXPECT_NE(e.find("no parameter 'bta' (did you mean 'beta'?)"), std::string::npos) << e;
  e = error_of(head + "v, NoSuchThing\n");
  EXPECT_NE(e.find("unknown component type 'NoSuchThing'"), std::string::npos) << e;
  e = error_of(head + "v, HydraulicVolumC\n");
  EXPECT_NE(e.find("unknown component type 'HydraulicVolumC' (did you mean HydraulicVolumeC?)"), std::string::npos) << e;
  e = error_of(head + "a, HydraulicVolumeC, ports=1\nb, HydraulicVolumeC, ports=1\n*CONNECT\na.P1, b.P1\n");
  EXPECT_NE(e.find("model.tlm:8: 'a.P1' and 'b.P1' are both C-type"), std::string::npos) << e;
  e = error_of(head + "a, HydraulicVolumeC, ports=1\n");
  EXPECT_NE(e.find("port a.P1 is not connected"), std::string::npos) << e;
  e = error_of(head + "a, HydraulicVolumeC, V=-1\n");
  EXPECT_NE(e.find("model.tlm:5: parameter V = -1 is outside the plausible range of a volume"), std::string::npos) << e;
  tlm::ModelSpec spec = tlm::parse_model(head + "a, HydraulicVolumeC, ports=1\n", "m.tlm");
  EXPECT_THROW(spec.apply_override("nobody.V=1"), std::invalid_argument);
  spec.apply_override("simulation.stoptime=2.5");
  EXPECT_EQ(spec.stop_time, 2.5);
  // Settings are checked once every override is in: a step that would be
  // 10¹³ steps against the old stop time is fine with the new one.
  spec.apply_override("simulation.timestep=1e-14");
  spec.apply_override("simulation.stoptime=1e-12");
  EXPECT_NO_THROW(spec.check_simulation());
  spec.apply_override("simulation.stoptime=1");
  EXPECT_THROW(spec.check_simulation(), config::InputError) << "10¹⁴ steps is not a run that ends";
}

TEST(FmuImporter, RefusesAnArchiveThatWritesOutsideItsFolder) {
  testing_support::TempDir dir;
  std::string path = dir.file("evil.fmu");
  int err = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  ASSERT_NE(z, nullptr);
  static const char text[] = "x";
  zip_file_add(z, "../escaped.txt", zip_source_buffer(z, text, 1, 0), 0);
  ASSERT_EQ(zip_close(z), 0);
  try {
    tlm::FmuArchive a(path);
    FAIL() << "an entry with .. must be refused";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("leaves the FMU folder"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::ifstream(dir.path() + "/../escaped.txt").good());
}

namespace {

// An FMU archive with the given entries (name → bytes).
std::string write_fmu(const testing_support::TempDir& dir, const std::string& name,
                      const std::vector<std::pair<std::string, std::string>>& entries) {
  const std::string path = dir.file(name);
  int err = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  EXPECT_NE(z, nullptr);
  for (const auto& [entry, bytes] : entries)
    zip_file_add(z, entry.c_str(), zip_source_buffer(z, bytes.data(), bytes.size(), 0), 0);
  EXPECT_EQ(zip_close(z), 0);
  return path;
}

std::string refusal(const std::string& path) {
  try {
    tlm::FmuArchive a(path);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(FmuImporter, RefusesAModelIdentifierThatIsNotACIdentifier) {
  // "../../../x" made tlm_host dlopen a library outside the FMU (its
  // constructor ran). The name is now refused before any library is loaded.
  testing_support::TempDir dir;
  for (const char* id : {"../../../x", "a/b", "9lives", "a b"}) {
    const std::string md = std::string("<?xml version=\"1.0\"?><fmiModelDescription fmiVersion=\"2.0\" ") +
                           "modelName=\"m\" guid=\"{1}\"><CoSimulation modelIdentifier=\"" + id +
                           "\"/><ModelVariables/></fmiModelDescription>";
    const std::string e = refusal(write_fmu(dir, "id.fmu", {{"modelDescription.xml", md}}));
    EXPECT_NE(e.find("is not a C identifier"), std::string::npos) << id << ": " << e;
    EXPECT_EQ(e.find("cannot load"), std::string::npos) << id << ": no library may be tried: " << e;
  }
}

TEST(FmuImporter, StopsUnpackingAtItsLimitAndLeavesNoFolder) {
  testing_support::TempDir dir, unpack;
  const std::string fmu = write_fmu(dir, "bomb.fmu", {{"zeros.bin", std::string(2000000, '\0')}});
  const char* old_tmp = std::getenv("TMPDIR");
  const std::string saved = old_tmp ? old_tmp : "";
  setenv("TMPDIR", unpack.path().c_str(), 1);     // the importer's folder goes here
  setenv("PCS_FMU_MAX_UNPACKED", "1000000", 1);  // 1 MB for this test
  const std::string e = refusal(fmu);
  unsetenv("PCS_FMU_MAX_UNPACKED");
  if (old_tmp) setenv("TMPDIR", saved.c_str(), 1); else unsetenv("TMPDIR");
  EXPECT_NE(e.find("unpacks to more than 1000000 bytes"), std::string::npos) << e;
  int left = 0;
  for (const auto& entry : std::filesystem::directory_iterator(unpack.path())) left += entry.path().filename().string().rfind("tlm_host_fmu_", 0) == 0;
  EXPECT_EQ(left, 0) << "the importer's temporary folder is removed";
  EXPECT_EQ(tlm::fmu_unpack_limit(), 1ull << 30) << "1 GiB without the variable";
}

TEST(FmuImporter, ReadsTheGeneratedModelDescriptionAndCleansUp) {
  std::string dir;
  {
    tlm::FmuArchive a(PCS_ONE_DOF_FMU);
    dir = a.dir();
    const auto& md = a.description();
    EXPECT_EQ(md.model_identifier, "one_dof");
    ASSERT_NE(md.find("cavity.q"), nullptr);
    EXPECT_EQ(md.find("cavity.q")->causality, "output");
    EXPECT_EQ(md.find("cavity.q")->type, "Real");
    EXPECT_EQ(md.find("cavity.q")->unit, "m3/s") << "host.h5 logs the FMU's outputs with this unit";
    EXPECT_EQ(md.find("server.host")->type, "String");
    EXPECT_EQ(md.find("server.host")->unit, "");
  }
  EXPECT_FALSE(std::ifstream(dir + "/modelDescription.xml").good()) << "the temporary folder must be removed";
}

// A Real's unit is its own attribute or, in another exporter's FMU, its
// declaredType's (FMI 2.0 §2.2.7); the host logs each FMU output with it.
TEST(FmuImporter, TakesARealsUnitFromItselfOrItsDeclaredType) {
  const std::string xml =
      "<?xml version=\"1.0\"?>\n<fmiModelDescription fmiVersion=\"2.0\" modelName=\"m\" guid=\"{g}\">\n"
      "<CoSimulation modelIdentifier=\"m\"/>\n<UnitDefinitions><Unit name=\"Pa\"/></UnitDefinitions>\n"
      "<TypeDefinitions><SimpleType name=\"Pressure\"><Real quantity=\"Pressure\" unit=\"Pa\"/></SimpleType>"
      "</TypeDefinitions>\n<ModelVariables>\n"
      "<ScalarVariable name=\"a.p\" valueReference=\"0\" causality=\"output\"><Real declaredType=\"Pressure\"/>"
      "</ScalarVariable>\n"
      "<ScalarVariable name=\"a.q\" valueReference=\"1\" causality=\"output\"><Real unit=\"m3/s\"/></ScalarVariable>\n"
      "<ScalarVariable name=\"a.p2\" valueReference=\"2\" causality=\"output\">"
      "<Real declaredType=\"Pressure\" unit=\"bar\"/></ScalarVariable>\n"
      "<ScalarVariable name=\"n\" valueReference=\"3\" causality=\"output\"><Integer/></ScalarVariable>\n"
      "</ModelVariables>\n</fmiModelDescription>\n";
  const auto md = tlm::parse_model_description(xml, "test.xml");
  ASSERT_NE(md.find("a.p"), nullptr);
  EXPECT_EQ(md.find("a.p")->unit, "Pa") << "from its declaredType";
  EXPECT_EQ(md.find("a.q")->unit, "m3/s");
  EXPECT_EQ(md.find("a.p2")->unit, "bar") << "its own unit overrides the type's";
  EXPECT_EQ(md.find("n")->unit, "");
}

// *LOG (or --log) keeps the results to what a study reads: the rig scene's
// host wrote 168 series at 20 us, 67 MB per simulated second, where its
// reports and plots read a dozen. A series or a group is kept, the time and
// the *REPORT's series always (a report on a file without them would fail
// after the run); an entry that names nothing is refused at its line with
// what its group holds, before the results file is created.
TEST(ModelFile, LogKeepsTheNamedSeriesTheTimeAndTheReportsAndRefusesAnUnknownOne) {
  testing_support::TempDir dir;
  const std::string model =
      "*SIMULATION\ntimestep, 1e-5\nstoptime, 1e-3\n*COMPONENT\n"
      "src, PressureSourceC, p=1e7\norifice, HydraulicTurbulentOrificeQ, Cd=0.7, A=1e-6\n"
      "vol, HydraulicVolumeC, V=1e-4, ports=2\nleak, LaminarOrificeQ, Kc=1e-12\ntank, PressureSourceC, p=1e5\n"
      "*CONNECT\nsrc.P1, orifice.P1\norifice.P2, vol.P1\nvol.P2, leak.P1\nleak.P2, tank.P1\n";
  auto series_of = [](const std::string& h5) {
    std::vector<std::string> names;
    for (const auto& [name, rows] : h5io::list_series(h5)) names.push_back(name);
    return names;
  };
  {
    tlm::System all(tlm::read_model(write_model(dir, model)));
    all.run(dir.file("all.h5"), false);
  }
  tlm::ModelSpec spec = tlm::read_model(write_model(dir, model + "*LOG\ncomponents/vol, nodes/vol.P1/p\n"));
  ASSERT_EQ(spec.log_only.size(), 2u);
  EXPECT_EQ(spec.log_only[1].second.line, 16) << "each entry keeps its line";
  {
    tlm::System some(std::move(spec));
    some.run(dir.file("some.h5"), false);
  }
  const std::vector<std::string> every = series_of(dir.file("all.h5")), kept = series_of(dir.file("some.h5"));
  std::vector<std::string> expected;
  for (const std::string& n : every)
    if (n == "time" || n == "nodes/vol.P1/p" || n.rfind("components/vol/", 0) == 0) expected.push_back(n);
  EXPECT_GT(every.size(), expected.size() + 4) << "the full file has the other nodes and components too";
  EXPECT_GE(expected.size(), 4u);
  EXPECT_EQ(kept, expected);
  EXPECT_EQ(h5io::read_series(dir.file("some.h5"), "nodes/vol.P1/p"), h5io::read_series(dir.file("all.h5"), "nodes/vol.P1/p"))
      << "a kept series is the same series";

  // A report's series are kept whatever *LOG says.
  tlm::ModelSpec reported;
  reported.log_only.emplace_back("nodes/vol.P1/p", config::SourceLocation{"m.tlm", 3});
  reported.report = tlm::parse_model("*REPORT\npiston, vol\ninlet_p, nodes/src.P1/p\npeak, p_v, nodes/vol.P2/p\n"
                                     "*SIMULATION\ntimestep, 1e-5\nstoptime, 1e-3\n*COMPONENT\nvol, HydraulicVolumeC\n",
                                     "r.tlm").report;
  reported.components.push_back({});
  reported.components.back().name = "vol";
  tlm::report_settings(reported);
  std::vector<std::string> logged;
  for (const auto& [entry, where] : reported.log_only) logged.push_back(entry);
  for (const char* n : {"components/vol/x", "components/vol/v", "components/vol/F_contact", "nodes/src.P1/p", "nodes/vol.P2/p"})
    EXPECT_NE(std::find(logged.begin(), logged.end(), n), logged.end()) << n;

  try {
    tlm::System bad(tlm::read_model(write_model(dir, model + "*LOG\ncomponents/vol, components/vol/pressure\n")));
    ADD_FAILURE() << "an unknown series was accepted";
  } catch (const config::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("model.tlm:16: *LOG: the model has no series or group 'components/vol/pressure' (components/vol holds "),
              std::string::npos) << what;
    EXPECT_NE(what.find("V_void"), std::string::npos) << what;
  }
}
