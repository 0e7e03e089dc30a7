// Axisymmetric decks in LS-DYNA's 2D conventions (*SECTION_SHELL ELFORM 15,
// *ELEMENT_SHELL, x the radius, y the axis) and the coaxial bar impact
// measured at gauges: shared by the axisymmetric tests and the benchmark.
#pragma once

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "input/deck_reader.hpp"
#include "solver/solver.hpp"

namespace axi_test {

constexpr double kRho = 7850.0, kE = 210e9;

// A structured block of quads: nr × ny cells over [r0, r1] × [y0, y1], part
// `pid`, node and element ids from `first_id`. Writes *NODE and
// *ELEMENT_SHELL cards (counter-clockwise in the x–y plane).
inline std::string block(int pid, int first_id, double r0, double r1, int nr, double y0, double y1, int ny) {
  std::ostringstream d;
  d.precision(17);
  d << "*NODE\n";
  auto nid = [&](int i, int j) { return first_id + j * (nr + 1) + i; };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nr; ++i)
      d << nid(i, j) << "," << r0 + (r1 - r0) * i / nr << "," << y0 + (y1 - y0) * j / ny << ",0\n";
  d << "*ELEMENT_SHELL\n";
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nr; ++i)
      d << first_id + j * nr + i << "," << pid << "," << nid(i, j) << "," << nid(i + 1, j) << "," << nid(i + 1, j + 1)
        << "," << nid(i, j + 1) << "\n";
  return d.str();
}

// Two coaxial cylinders, x the radius and y the axis: a piston (part 1,
// radius rp, length Lp) moving at −v0 along y onto a tool (part 2, radius rt,
// length Lt) below it, 0.1 mm apart; cells of about h; steel with Poisson's
// ratio nu; 2D contact between the two parts with vdc % of critical damping
// (0: the elastic interface of the 1D theory; 20: as the 3D impact decks)
// and stiffness factor sfact.
inline std::string bar_impact_deck(double Lp, double rp, double Lt, double rt, double h, double v0, double nu,
                                   double vdc, double sfact = 1.0) {
  const int nrp = std::max(1, static_cast<int>(std::lround(rp / h))), nrt = std::max(1, static_cast<int>(std::lround(rt / h)));
  std::ostringstream d;
  d.precision(17);
  d << "*KEYWORD\n*TITLE\naxisymmetric bar impact\n";
  d << block(2, 1, 0.0, rt, nrt, -Lt, 0.0, static_cast<int>(std::lround(Lt / h)));
  d << block(1, 1000000, 0.0, rp, nrp, 1e-4, 1e-4 + Lp, static_cast<int>(std::lround(Lp / h)));
  d << "*PART\npiston\n1,1,1\n*PART\ntool\n2,1,1\n*SECTION_SHELL\n1,15\n0,0,0,0\n";
  d << "*MAT_ELASTIC\n1," << kRho << "," << kE << "," << nu << "\n";
  d << "*SET_PART_LIST\n1\n1\n*SET_PART_LIST\n2\n2\n";
  d << "*CONTACT_2D_AUTOMATIC_SURFACE_TO_SURFACE\n1,2," << sfact << "\n0,1e20\n0," << vdc << "\n";
  d << "*INITIAL_VELOCITY_GENERATION\n1,2,0,0," << -v0 << ",0\n0,0,0,0,0,0\n";
  return d.str();
}

struct Gauge {
  double depth = 0;            // below the tool's top, m
  std::vector<size_t> elems;   // the layer of tool elements there
  std::vector<double> weight;  // their ring volumes, for the section mean
  std::vector<double> sigma;   // section-mean axial stress per step, Pa
};

struct Impact {
  std::vector<double> t;
  std::vector<Gauge> gauges;
  double ke0 = 0, area_tool = 0, max_balance = 0;
  double contact_energy = 0, hourglass = 0, damping = 0;  // at t_end, J
  double piston_energy_end = 0;                            // kinetic energy left in the piston at t_end, J
  size_t elements = 0;
  long steps = 0;
};

// Runs the impact to t_end, recording the section-mean axial stress at each gauge depth.
inline Impact run_bar_impact(double Lp, double rp, double Lt, double rt, double h, double v0, double nu,
                             std::vector<double> depths, double t_end, double vdc, double sfact = 1.0) {
  fe::Model m = fe::parse_deck(bar_impact_deck(Lp, rp, Lt, rt, h, v0, nu, vdc, sfact), "axi_impact.k");
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  fe::Solver s(m, dt);
  Impact out;
  out.elements = m.axis.size();
  out.area_tool = M_PI * rt * rt;
  for (double depth : depths) {
    Gauge g;
    g.depth = depth;
    for (size_t e = 0; e < m.axis.size(); ++e) {
      if (m.axis[e].part != 2) continue;
      double yc = 0.0, rc = 0.0;
      for (int k = 0; k < 4; ++k) {
        yc += 0.25 * m.x0[static_cast<size_t>(m.axis[e].n[k])].y();
        rc += 0.25 * m.x0[static_cast<size_t>(m.axis[e].n[k])].x();
      }
      if (std::fabs(yc + depth) < 0.5 * h * 1.01) {
        g.elems.push_back(e);
        g.weight.push_back(rc);  // equal cell widths: the ring volume is proportional to r_c
      }
    }
    out.gauges.push_back(g);
  }
  double ke0 = 0.0;
  for (size_t i = 0; i < m.x0.size(); ++i) ke0 += 0.5 * m.mass[i] * m.v0[i].squaredNorm();
  out.ke0 = ke0;
  while (s.time() < t_end) {
    s.step();
    out.t.push_back(s.time());
    for (auto& g : out.gauges) {
      double sum = 0.0, w = 0.0;
      for (size_t k = 0; k < g.elems.size(); ++k) {
        sum += g.weight[k] * s.axi_stress(g.elems[k])(1);
        w += g.weight[k];
      }
      g.sigma.push_back(w > 0.0 ? sum / w : 0.0);
    }
    out.max_balance = std::max(out.max_balance, std::fabs(s.energies().balance_error));
    out.contact_energy = s.energies().contact;
    out.hourglass = s.energies().hourglass;
    out.damping = s.energies().damping;
    ++out.steps;
  }
  for (size_t i = 0; i < m.x0.size(); ++i)
    if (m.node_ids[i] >= 1000000) out.piston_energy_end += 0.5 * m.mass[i] * s.v()[i].squaredNorm();
  return out;
}

// The compressive pulse of a gauge: its arrival (first 50 % crossing of the
// peak), its end (last 50 % crossing), the mean over the central 60 % and the
// 10–90 % rise time of the leading edge.
struct Pulse {
  double start = 0, end = 0, plateau = 0, rise = 0, peak = 0;
};
inline Pulse pulse_of(const std::vector<double>& t, const std::vector<double>& sigma) {
  Pulse p;
  for (double s : sigma) p.peak = std::min(p.peak, s);
  size_t a = 0, b = 0;
  for (size_t i = 0; i < sigma.size(); ++i)
    if (sigma[i] < 0.5 * p.peak) {
      if (!a) a = i;
      b = i;
    }
  p.start = t[a], p.end = t[b];
  double sum = 0.0;
  int n = 0;
  for (size_t i = 0; i < t.size(); ++i)
    if (t[i] > p.start + 0.2 * (p.end - p.start) && t[i] < p.end - 0.2 * (p.end - p.start)) sum += sigma[i], ++n;
  p.plateau = n ? sum / n : 0.0;
  double t10 = 0, t90 = 0;
  for (size_t i = 0; i < sigma.size() && t[i] <= p.start + 0.5 * (p.end - p.start); ++i) {
    if (!t10 && sigma[i] < 0.1 * p.plateau) t10 = t[i];
    if (!t90 && sigma[i] < 0.9 * p.plateau) t90 = t[i];
  }
  p.rise = t90 - t10;
  return p;
}

}  // namespace axi_test
