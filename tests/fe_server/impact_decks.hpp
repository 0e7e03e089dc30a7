// Coaxial bar-impact decks and a run that measures the pulse at a gauge,
// shared by the element tests and the hard-case tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "loads/cavity_load.hpp"
#include "input/deck_reader.hpp"
#include "input/mesher.hpp"
#include "solver/solver.hpp"

namespace fe_test {

constexpr double kRho = 7850.0, kE = 210e9;

// Two coaxial cylinders of radius r along z: a piston (part 1) of length Lp
// moving at −v0 towards a tool (part 2) of length Lt below it, 0.1 mm apart.
// vdc: the contact's viscous damping in % of critical (VDC).
inline std::string bar_impact_deck(double Lp, double Lt, double r, double h, double v0, double E_tool, double sfs = 1.0,
                                   double nu = 0.0, double vdc = 20.0) {
  fe::RevolutionMeshOptions tool, piston;
  tool.element_size = piston.element_size = h;
  tool.part = 2;
  tool.z0 = -Lt;
  tool.title = "tool";
  tool.node_offset = 0, tool.element_offset = 0, tool.set_offset = 0;
  fe::RevolutionMesh mt = fe::mesh_revolution({{Lt, r, 0.0}}, tool);
  piston.part = 1;
  piston.z0 = 1e-4;
  piston.title = "piston";
  piston.node_offset = 100000, piston.element_offset = 100000, piston.set_offset = 10;
  fe::RevolutionMesh mp = fe::mesh_revolution({{Lp, r, 0.0}}, piston);
  std::ostringstream d;
  d << "*KEYWORD\n" << mt.keyword_text << mp.keyword_text;
  d << "*PART\npiston\n1,1,1\n*PART\ntool\n2,1,2\n*SECTION_SOLID\n1,1\n";
  d << "*MAT_ELASTIC\n1," << kRho << "," << kE << "," << nu << "\n2," << kRho << "," << E_tool << "," << nu << "\n";
  // Tool top face: set 2 (z = 0 facing +z); piston bottom face: set 11.
  d << "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n11,2,0,0\n0,0,0,0," << vdc << "\n" << sfs << "\n";
  d << "*INITIAL_VELOCITY_GENERATION\n1,2,0,0,0," << -v0 << "\n0,0,0,0,0,0\n";
  return d.str();
}

struct ImpactResult {
  double sigma_plateau = 0, pulse_length = 0, W = 0, piston_v_after = 0, max_penetration = 0, max_balance = 0;
  double ke0 = 0, area = 0;
  // At the end: kinetic + internal energy, and what hourglass control and
  // the contact took (each a share of ke0 once divided by it).
  double ke_ie_end = 0, hourglass_end = 0, contact_end = 0, damping_end = 0;
};

// Run the impact and measure at a gauge in the tool, `gauge` below its top.
inline ImpactResult run_impact(double Lp, double Lt, double h, double v0, double E_tool, double gauge, double t_end,
                               double sfs = 1.0, double vdc = 20.0) {
  const double r = 0.01;
  fe::Model m = fe::parse_deck(bar_impact_deck(Lp, Lt, r, h, v0, E_tool, sfs, 0.0, vdc), "impact.k");
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  fe::Solver s(m, dt);
  // Gauge: tool elements whose centre lies in the layer at z = −gauge.
  std::vector<size_t> gauge_elems;
  for (size_t e = 0; e < m.solids.size(); ++e) {
    if (m.solids[e].part != 2) continue;
    double zc = 0.0;
    for (int k = 0; k < 8; ++k) zc += m.x0[static_cast<size_t>(m.solids[e].n[k])].z() / 8.0;
    if (std::fabs(zc + gauge) < 0.5 * h * 1.01) gauge_elems.push_back(e);
  }
  EXPECT_FALSE(gauge_elems.empty());
  ImpactResult res;
  std::vector<double> sig;
  double W = 0.0, above = 0.0;
  // The tool's cross-section as meshed (its top face, set 2): the O-grid's
  // polygon is a few per cent smaller than πr², and W must use the real one.
  double A = 0.0;
  for (const auto& seg : m.segment_sets.at(2)) A += fe::segment_area_vector(seg, m.x0).norm();
  res.area = A;
  const double c_t = std::sqrt(E_tool / kRho);
  while (s.time() < t_end) {
    s.step();
    double sz = 0.0;
    for (size_t e : gauge_elems) sz += s.stress(e)(2);
    sz /= static_cast<double>(gauge_elems.size());
    sig.push_back(sz);
    W += A * c_t / E_tool * sz * sz * dt;
    res.max_penetration = std::max(res.max_penetration, s.max_penetration());
    res.max_balance = std::max(res.max_balance, std::fabs(s.energies().balance_error));
    if (s.step_count() == 1) res.ke0 = s.energies().kinetic;
  }
  std::vector<double> comp;
  for (double v : sig)
    if (v < -1e6) comp.push_back(v);
  std::sort(comp.begin(), comp.end());
  res.sigma_plateau = comp.empty() ? 0.0 : comp[comp.size() / 2];  // median over the pulse
  // Pulse length: full width at half the plateau (the front's rise and fall are symmetric about it).
  for (double v : sig)
    if (v < 0.5 * res.sigma_plateau) above += dt;
  res.pulse_length = above;
  res.W = W;
  // Piston's mean velocity at the end.
  double p = 0.0, mass = 0.0;
  for (size_t i = 0; i < m.x0.size(); ++i)
    if (m.node_ids[i] > 100000) {
      p += m.mass[i] * s.v()[i].z();
      mass += m.mass[i];
    }
  res.piston_v_after = p / mass;
  const fe::Energies& en = s.energies();
  res.ke_ie_end = en.kinetic + en.internal;
  res.hourglass_end = en.hourglass;
  res.contact_end = en.contact;
  res.damping_end = en.damping;
  return res;
}

}  // namespace fe_test
