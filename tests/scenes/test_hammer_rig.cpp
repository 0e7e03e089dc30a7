// The hammer reworked against the rig (scenes/hammer_rig): the acceptance
// figures of the validated-hammer work on the monolithic model, in its four
// running conditions. The bands are the rig's: the thesis' Table 2 flows
// (Andersson 2018) give the ratios 0.825 / 0.847 / 0.738; the accepted bands
// around them are the issue's, as are ±10 % per flow, ±1 % on the operating
// pressure and 15–30 Hz. Each run is the scene's own 1.2 s (13–21 blows after
// the report's 0.3 s settle), so the figures are what the scene reports.
#include <gtest/gtest.h>

#include "calibration.hpp"
#include "model.hpp"
#include "process.hpp"

namespace {

struct Case {
  const char* name;
  const char* p_crack;  // the relief setting the scene's header gives for this case
  const char* area;     // m²
  double p_set_abs;     // the operating pressure, absolute (gauge + 1.013 bar)
  double q_measured;    // l/min, thesis Table 2
};

tlm::PercussionFigures run_case(const Case& c) {
  testing_support::TempDir dir;
  return tlm::run_percussion(tlm::read_model(PCS_SCENES_DIR "/hammer_rig/model.tlm"),
                             {std::string("relief.p_crack=") + c.p_crack, std::string("restrictor.A=") + c.area},
                             dir.file("r.h5"));
}

}  // namespace

TEST(HammerRig, FlowFollowsTheRestrictorAndThePressureAsOnTheRig) {
  const Case cases[] = {{"11", "14741097.54", "2.827e-5", 151.013e5, 80.0},
                        {"12", "14745173.05", "2.290e-5", 151.013e5, 66.0},
                        {"21", "9719834.464", "2.827e-5", 101.013e5, 59.0},
                        {"22", "9622778.39", "2.290e-5", 101.013e5, 50.0}};
  double q[4];
  for (int i = 0; i < 4; ++i) {
    const tlm::PercussionFigures f = run_case(cases[i]);
    q[i] = f.q_in * 6e4;
    SCOPED_TRACE(std::string("case ") + cases[i].name);
    EXPECT_NEAR(q[i] / cases[i].q_measured, 1.0, 0.10) << q[i] << " l/min";
    EXPECT_NEAR(f.p_in / cases[i].p_set_abs, 1.0, 0.01) << f.p_in << " Pa";
    EXPECT_GE(f.frequency, 15.0);
    EXPECT_LE(f.frequency, 30.0);
    EXPECT_GE(f.blows, 13);  // whole cycles after the settle time that the figures average
  }
  const double d150 = q[1] / q[0], d100 = q[3] / q[2], p60 = q[2] / q[0];
  EXPECT_GE(d150, 0.80);
  EXPECT_LE(d150, 0.86);
  EXPECT_GE(d100, 0.82);
  EXPECT_LE(d100, 0.88);
  EXPECT_GE(p60, 0.71);
  EXPECT_LE(p60, 0.79);
}
