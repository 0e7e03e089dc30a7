// fe_server cost and accuracy, in one run:
//  (1) ns per element-cycle (hex8, one core) against model size: a free
//      steel cylinder with an initial velocity field, stepping only;
//  (2) ns per element-cycle of 1D bar elements;
//  (3) coaxial bar impact (steel Ø20 mm, piston 0.2 m at 8 m/s on a 0.8 m
//      tool, ν = 0): error in plateau stress and in W = (A·c/E)∫σ²dt against
//      1D theory, and wall time, for three mesh sizes;
//  (4) ns per element-cycle of the axisymmetric quad against model size;
//  (5) the same bar impact with axisymmetric quads: the Pareto points to
//      set beside (3), hex8 against axisymmetric at equal error;
//  (6) the hammer scene's deck (rigid piston, spool and rock block, 1D-bar
//      tool) on its own: µs per FE step at the co-simulation's 1 µs step;
//  (7) thread scaling, 1 → 2 threads, hex8 and axisymmetric decks of
//      30k+ elements, the two counts interleaved three times (median);
//  (8) against CalculiX (ccx, Debian's calculix-ccx; skipped without it):
//      the bar impact's h = 2.5 mm hex8 mesh as C3D8R, explicit, one
//      thread each, output only at the end;
//  (9) fatigue counting's cost; (10) tet4 beside hex8 on one block.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "axi_decks.hpp"
#include "block_decks.hpp"
#include "loads/cavity_load.hpp"
#include "input/deck_reader.hpp"
#include "input/mesher.hpp"
#include "config/port_table.hpp"
#include "config/version.hpp"
#include "output/fatigue.hpp"
#include "solver/solver.hpp"

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// ns per element-cycle of `steps` steps of s, timed in five equal slices:
// the fastest slice is the estimate (interference from the rest of a shared
// machine only adds time), the median and the slowest show the noise.
struct SliceTiming {
  double fastest, median, slowest;
};
SliceTiming time_in_slices(fe::Solver& s, int steps, size_t elements) {
  constexpr int kSlices = 5;
  const int per = std::max(1, steps / kSlices);
  std::vector<double> ns;
  for (int r = 0; r < kSlices; ++r) {
    auto t0 = Clock::now();
    for (int k = 0; k < per; ++k) s.step();
    ns.push_back(1e9 * since(t0) / (static_cast<double>(per) * static_cast<double>(elements)));
  }
  std::sort(ns.begin(), ns.end());
  return {ns.front(), ns[kSlices / 2], ns.back()};
}

std::string materials(double nu) {
  std::ostringstream d;
  d << "*PART\np\n1,1,1\n*PART\nt\n2,1,1\n*SECTION_SOLID\n1,1\n*MAT_ELASTIC\n1,7850,2.1e11," << nu << "\n";
  return d.str();
}

void element_cycle_cost() {
  std::printf("hex8 element-cycle cost (free cylinder, one core):\n  %10s %10s %12s\n", "elements", "steps", "ns/el-cycle");
  for (double h : {0.01, 0.006, 0.004}) {
    fe::RevolutionMeshOptions o;
    o.element_size = h;
    fe::RevolutionMesh mesh = fe::mesh_revolution({{0.4, 0.03, 0.0}}, o);
    fe::Model m = fe::parse_deck("*KEYWORD\n" + mesh.keyword_text + materials(0.3), "cyl.k");
    for (size_t i = 0; i < m.x0.size(); ++i) m.v0[i] = fe::Vec3(0, 0, 1.0 * m.x0[i].z());  // stretching
    fe::Solver s(m, 0.9 * fe::Solver::stable_dt(m).dt);
    const int steps = std::max(20, static_cast<int>(4e6 / m.solids.size()));
    const SliceTiming t = time_in_slices(s, steps, m.solids.size());
    std::printf("  %10zu %10d %12.1f (median %.1f, slowest %.1f)\n", m.solids.size(), steps, t.fastest, t.median, t.slowest);
    std::printf("csv:fe_cost,hex8,%zu,%.2f,%.2f,%.2f\n", m.solids.size(), t.fastest, t.median, t.slowest);
  }
}

// (10) tet4 beside hex8: one 24×24×24-cell block (13824 cells) meshed
// both ways, stretching, timed interleaved three times each on one core:
// ns per element-cycle, and per cell-cycle (a tetrahedral mesh of the
// same resolution has six elements per cell, and its step is shorter).
void tet4_cycle_cost() {
  std::printf("tet4 beside hex8 (24^3-cell block, one core, interleaved):\n");
  fe::Model hex = fe::parse_deck(fe_test::block_deck(24, 24, 24, 2e-3, false, 2.1e11, 0.3).deck, "hex.k");
  fe::Model tet = fe::parse_deck(fe_test::block_deck(24, 24, 24, 2e-3, true, 2.1e11, 0.3).deck, "tet.k");
  std::vector<double> per_element[2], steps_ratio;
  fe::Model* models[2] = {&hex, &tet};
  double dt[2];
  for (int k = 0; k < 2; ++k) {
    for (size_t i = 0; i < models[k]->x0.size(); ++i) models[k]->v0[i] = fe::Vec3(0, 0, 1.0 * models[k]->x0[i].z());
    dt[k] = 0.9 * fe::Solver::stable_dt(*models[k]).dt;
  }
  for (int round = 0; round < 3; ++round)
    for (int k = 0; k < 2; ++k) {
      fe::Solver s(*models[k], dt[k]);
      s.set_threads(1);
      const size_t n = models[k]->solids.size();
      const SliceTiming t = time_in_slices(s, std::max(20, static_cast<int>(4e6 / static_cast<double>(n))), n);
      per_element[k].push_back(t.fastest);
    }
  for (int k = 0; k < 2; ++k) std::sort(per_element[k].begin(), per_element[k].end());
  const double h = per_element[0].front(), t = per_element[1].front();
  std::printf("  hex8 %zu elements: %.1f ns/element-cycle (of 3: %.1f-%.1f); step %.3g s\n", hex.solids.size(), h,
              per_element[0].front(), per_element[0].back(), dt[0]);
  std::printf("  tet4 %zu elements: %.1f ns/element-cycle (of 3: %.1f-%.1f); step %.3g s\n", tet.solids.size(), t,
              per_element[1].front(), per_element[1].back(), dt[1]);
  std::printf("  per cell and simulated second: tet4 costs %.1fx hex8 (6 elements per cell, steps %.2fx as many)\n",
              6.0 * t / h * dt[0] / dt[1], dt[0] / dt[1]);
  std::printf("csv:tet4_cost,%zu,%.2f,%.2f,%.4g,%zu,%.2f,%.2f,%.4g\n", hex.solids.size(), h, per_element[0].back(), dt[0],
              tet.solids.size(), t, per_element[1].back(), dt[1]);
}

void bar_cycle_cost() {
  std::ostringstream d;
  const int n = 20000;
  d << "*KEYWORD\n*NODE\n";
  for (int i = 0; i <= n; ++i) d << i + 1 << ",0,0," << 0.001 * i << "\n";
  d << "*PART\nbar\n1,1,1\n*SECTION_BEAM\n1,3\n1e-4\n*MAT_ELASTIC\n1,7850,2.1e11,0.3\n*ELEMENT_BEAM\n";
  for (int i = 0; i < n; ++i) d << i + 1 << ",1," << i + 1 << "," << i + 2 << "\n";
  fe::Model m = fe::parse_deck(d.str(), "bar.k");
  for (size_t i = 0; i < m.x0.size(); ++i) m.v0[i] = fe::Vec3(0, 0, m.x0[i].z());
  fe::Solver s(m, 0.9 * fe::Solver::stable_dt(m).dt);
  const SliceTiming t = time_in_slices(s, 500, static_cast<size_t>(n));
  std::printf("1D bar element-cycle cost: %.1f ns (%d elements; median %.1f, slowest %.1f)\n", t.fastest, n, t.median,
              t.slowest);
  std::printf("csv:fe_cost,bar,%d,%.2f,%.2f,%.2f\n", n, t.fastest, t.median, t.slowest);
}

void bar_impact_convergence() {
  const double E = 2.1e11, rho = 7850, c = std::sqrt(E / rho), v0 = 8.0, Lp = 0.2, Lt = 0.8, r = 0.01;
  std::printf("bar impact vs 1D theory (sigma = E*v0/2c = %.1f MPa, W = m*v0^2/2):\n", E * v0 / (2 * c) / 1e6);
  std::printf("  %8s %7s %9s %12s %10s %10s\n", "h [mm]", "dt/dt_c", "elements", "sigma err %", "W err %", "wall [s]");
  // Mesh refinement, and the time step at 0.9 (LS-DYNA's TSSFAC default) and
  // half of that: speed against error for the recommended-setting choice.
  for (double h : {0.01, 0.005, 0.0025})
  for (double factor : {0.9, 0.45}) {
    fe::RevolutionMeshOptions t, p;
    t.element_size = p.element_size = h;
    t.part = 2, t.z0 = -Lt, t.gauges = {-0.2};
    p.part = 1, p.z0 = 1e-4, p.node_offset = 1000000, p.element_offset = 1000000, p.set_offset = 10;
    std::string deck = "*KEYWORD\n" + fe::mesh_revolution({{Lt, r, 0}}, t).keyword_text +
                       fe::mesh_revolution({{Lp, r, 0}}, p).keyword_text + materials(0.0) +
                       "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n11,2,0,0\n0,0,0,0,20\n1\n"
                       "*INITIAL_VELOCITY_GENERATION\n1,2,0,0,0,-8\n0,0,0,0,0,0\n";
    fe::Model m = fe::parse_deck(deck, "impact.k");
    double A = 0;
    for (const auto& seg : m.segment_sets.at(2)) A += fe::segment_area_vector(seg, m.x0).norm();
    const double dt = factor * fe::Solver::stable_dt(m).dt;
    fe::Solver s(m, dt);
    std::vector<double> sig;
    double W = 0;
    auto t0 = Clock::now();
    while (s.time() < 0.2 / c + 4.0 * Lp / c) {  // the whole pulse past the gauge, tail included
      s.step();
      double sz = 0;
      for (int e : m.history_solids) sz += s.stress(static_cast<size_t>(e))(2);
      sz /= static_cast<double>(m.history_solids.size());
      sig.push_back(sz);
      W += A * c / E * sz * sz * dt;
    }
    const double wall = since(t0);
    std::vector<double> comp;
    for (double v : sig)
      if (v < -1e6) comp.push_back(v);
    std::sort(comp.begin(), comp.end());
    const double plateau = comp[comp.size() / 2];
    const double W_exact = 0.5 * rho * A * Lp * v0 * v0;
    const double e_sigma = 100 * (-plateau / (E * v0 / (2 * c)) - 1), e_W = 100 * (W / W_exact - 1);
    std::printf("  %8.1f %7.2f %9zu %12.2f %10.2f %10.2f\n", h * 1e3, factor, m.solids.size(), e_sigma, e_W, wall);
    std::printf("csv:fe_pareto,%g,%g,%zu,%.4f,%.4f,%.4f\n", h * 1e3, factor, m.solids.size(), e_sigma, e_W, wall);
  }
}
void axi_cycle_cost() {
  std::printf("axisymmetric quad element-cycle cost (free cylinder, one core):\n  %10s %10s %12s\n", "elements", "steps",
              "ns/el-cycle");
  for (double h : {0.005, 0.0025, 0.00125}) {
    const int nr = static_cast<int>(std::lround(0.03 / h)), ny = static_cast<int>(std::lround(0.4 / h));
    fe::Model m = fe::parse_deck("*KEYWORD\n" + axi_test::block(1, 1, 0.0, 0.03, nr, 0.0, 0.4, ny) +
                                     "*PART\np\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1,7850,2.1e11,0.3\n",
                                 "cyl2d.k");
    for (size_t i = 0; i < m.x0.size(); ++i) m.v0[i] = fe::Vec3(0, 1.0 * m.x0[i].y(), 0);  // stretching
    fe::Solver s(m, 0.9 * fe::Solver::stable_dt(m).dt);
    const int steps = std::max(20, static_cast<int>(2e7 / m.axis.size()));
    const SliceTiming t = time_in_slices(s, steps, m.axis.size());
    std::printf("  %10zu %10d %12.1f (median %.1f, slowest %.1f)\n", m.axis.size(), steps, t.fastest, t.median, t.slowest);
    std::printf("csv:fe_cost,axi4,%zu,%.2f,%.2f,%.2f\n", m.axis.size(), t.fastest, t.median, t.slowest);
  }
}

void axi_bar_impact_convergence() {
  const double E = 2.1e11, rho = 7850, c = std::sqrt(E / rho), v0 = 8.0, Lp = 0.2, Lt = 0.8, r = 0.01;
  std::printf("axisymmetric bar impact vs 1D theory (same case as above):\n");
  std::printf("  %8s %9s %12s %10s %10s\n", "h [mm]", "elements", "sigma err %", "W err %", "wall [s]");
  for (double h : {0.005, 0.0025, 0.00125}) {
    auto t0 = Clock::now();
    const auto res = axi_test::run_bar_impact(Lp, r, Lt, r, h, v0, 0.0, {0.2}, 0.2 / c + 4.0 * Lp / c, 20.0);  // as the hex8 deck
    const double wall = since(t0);
    std::vector<double> comp;
    double W = 0.0;
    for (size_t i = 0; i < res.t.size(); ++i) {
      const double sz = res.gauges[0].sigma[i];
      if (sz < -1e6) comp.push_back(sz);
      W += res.area_tool * c / E * sz * sz * (i ? res.t[i] - res.t[i - 1] : res.t[0]);
    }
    std::sort(comp.begin(), comp.end());
    const double plateau = comp[comp.size() / 2];
    const double W_exact = 0.5 * rho * res.area_tool * Lp * v0 * v0;
    const double e_sigma = 100 * (-plateau / (E * v0 / (2 * c)) - 1), e_W = 100 * (W / W_exact - 1);
    std::printf("  %8.2f %9zu %12.2f %10.2f %10.3f\n", h * 1e3, res.elements, e_sigma, e_W, wall);
    std::printf("csv:fe_pareto_axi,%g,0.9,%zu,%.4f,%.4f,%.4f\n", h * 1e3, res.elements, e_sigma, e_W, wall);
  }
}
void hammer_fe_step_cost() {
#ifdef PCS_HAMMER_DECK
  // Bare (elements, contacts, bodies), then with the cavity-pressure hook
  // applying fixed pressures on every hydraulic port, as it does between
  // two exchanges of a co-simulation.
  fe::Model m = fe::read_deck(PCS_HAMMER_DECK);
  const config::PortTable table = config::read_port_table(PCS_HAMMER_PORTS);
  fe::CavityPressureLoad load(m, table);
  for (size_t i = 0; i < load.slot_count(); ++i) load.set_pressure(static_cast<int>(i), 5e6);
  for (int mode : {0, 1, 2}) {  // bare, fixed pressures, TLM waves
    const bool loaded = mode > 0;
    if (mode == 2)
      for (size_t i = 0; i < load.slot_count(); ++i) load.set_wave(static_cast<int>(i), 5e6, 1e10);
    fe::Solver s(m, 1e-6);
    if (loaded) s.set_user_load(&load);
    for (int k = 0; k < 1000; ++k) s.step();  // warm caches and branch predictors
    // Five slices of 5000 steps: the fastest is the figure (a shared
    // machine only adds time). 26 ms in all: the fixed pressures, with no
    // oil to answer the piston's motion, drive it out of the model's box by
    // 34 ms, where the run-quality guard stops the run (slices of 20000
    // steps ended there with an uncaught error).
    double us = 1e300;
    for (int slice = 0; slice < 5; ++slice) {
      const int steps = 5000;
      auto t0 = Clock::now();
      for (int k = 0; k < steps; ++k) s.step();
      us = std::min(us, 1e6 * since(t0) / steps);
    }
    const char* what[] = {"", " with the cavity loads", " with the cavity loads as TLM waves"};
    const char* tag[] = {"bare", "loaded", "tlm"};
    std::printf("hammer deck, FE alone%s: %.2f us per FE step (%zu nodes, %zu in the per-node passes)\n",
                what[mode], us, m.x0.size(), s.active_nodes());
    std::printf("csv:hammer_fe_step,%s,%zu,%.3f\n", tag[mode], s.active_nodes(), us);
  }
#endif
}
// µs per step of `steps` steps on `threads` threads.
double step_time(const fe::Model& m, int threads, int steps) {
  fe::Solver s(m, 0.9 * fe::Solver::stable_dt(m).dt);
  s.set_threads(threads);
  for (int k = 0; k < 5; ++k) s.step();
  auto t0 = Clock::now();
  for (int k = 0; k < steps; ++k) s.step();
  return 1e6 * since(t0) / steps;
}

void thread_scaling() {
  std::printf("thread scaling (median of 3 interleaved runs):\n");
  fe::RevolutionMeshOptions o;
  o.element_size = 0.004;
  fe::Model hex = fe::parse_deck("*KEYWORD\n" + fe::mesh_revolution({{0.4, 0.03, 0.0}}, o).keyword_text + materials(0.3),
                                 "cyl.k");
  for (size_t i = 0; i < hex.x0.size(); ++i) hex.v0[i] = fe::Vec3(0, 0, 1.0 * hex.x0[i].z());
  fe::Model axi = fe::parse_deck("*KEYWORD\n" + axi_test::block(1, 1, 0.0, 0.06, 48, 0.0, 0.8, 640) +
                                     "*PART\np\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1,7850,2.1e11,0.3\n",
                                 "cyl2d.k");
  for (size_t i = 0; i < axi.x0.size(); ++i) axi.v0[i] = fe::Vec3(0, 1.0 * axi.x0[i].y(), 0);
  for (auto [name, model] : {std::pair<const char*, const fe::Model*>{"hex8", &hex}, {"axi4", &axi}}) {
    const size_t elements = model->solids.size() + model->axis.size();
    const int steps = static_cast<int>(std::max<size_t>(20, 6000000 / elements));
    std::vector<double> t1, t2, ratio;
    for (int rep = 0; rep < 3; ++rep) {
      t1.push_back(step_time(*model, 1, steps));
      t2.push_back(step_time(*model, 2, steps));
      ratio.push_back(t1.back() / t2.back());
    }
    std::vector<double> sorted = ratio;
    std::sort(sorted.begin(), sorted.end());
    std::sort(t1.begin(), t1.end());
    std::sort(t2.begin(), t2.end());
    std::printf("  %s, %zu elements: 1 thread %.1f us/step, 2 threads %.1f us/step (medians), speed-up %.2f "
                "(runs: %.2f %.2f %.2f)\n",
                name, elements, t1[1], t2[1], sorted[1], ratio[0], ratio[1], ratio[2]);
    std::printf("csv:fe_threads,%s,%zu,%.3f,%.3f,%.3f,%.3f,%.3f\n", name, elements, t1[1], t2[1], sorted[1], sorted[0],
                sorted[2]);
  }
}
// The cost of counting fatigue (*PCS_FATIGUE_PART) on every element: the FE
// step with and without the tracker's sample, interleaved, on the 2D
// cylinder of the thread benchmark (30720 axi4 elements) and a 3D one.
void fatigue_cost() {
  std::printf("fatigue counting on every element (signed von Mises, each FE step; 7 interleaved pairs):\n");
  const std::string card = "*PCS_FATIGUE_PART\n1,500e6,1e5,8,0,0,0,0\n0,1,0\n";
  auto cylinder = [&](int nr, int ny) {
    fe::Model a = fe::parse_deck("*KEYWORD\n" + axi_test::block(1, 1, 0.0, 0.06, nr, 0.0, 0.8 * ny / 640.0, ny) +
                                     "*PART\np\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1,7850,2.1e11,0.3\n" + card,
                                 "cyl2d.k");
    for (size_t i = 0; i < a.x0.size(); ++i) a.v0[i] = fe::Vec3(0, 1.0 * std::sin(20.0 * a.x0[i].y()), 0);
    return a;
  };
  // The hammer's size (its 928 elements fit the caches) and one 30 times larger.
  fe::Model small = cylinder(16, 64), axi = cylinder(48, 640);
  fe::RevolutionMeshOptions o;
  o.element_size = 0.004;
  fe::Model hex = fe::parse_deck("*KEYWORD\n" + fe::mesh_revolution({{0.4, 0.03, 0.0}}, o).keyword_text + materials(0.3) + card,
                                 "cyl.k");
  for (size_t i = 0; i < hex.x0.size(); ++i) hex.v0[i] = fe::Vec3(0, 0, 1.0 * std::sin(20.0 * hex.x0[i].z()));
  for (auto [name, model] : {std::pair<const char*, fe::Model*>{"axi4", &small}, {"axi4", &axi}, {"hex8", &hex}}) {
    const size_t elements = model->solids.size() + model->axis.size();
    const int steps = static_cast<int>(std::max<size_t>(20, 3000000 / elements));
    const double dt = 0.9 * fe::Solver::stable_dt(*model).dt;
    fe::Solver s(*model, dt);
    fe::FatigueTracker t(*model, dt);
    fe::Model every4 = *model;  // the same card sampling every 4th FE step (DT = 4 steps)
    every4.fatigue[0].dt = 4.0 * dt;
    fe::FatigueTracker t4(every4, dt);
    for (int k = 0; k < 5; ++k) s.step();
    std::vector<double> bare, counted, counted4;
    for (int rep = 0; rep < 7; ++rep) {
      auto t0 = Clock::now();
      for (int k = 0; k < steps; ++k) s.step();
      bare.push_back(1e6 * since(t0) / steps);
      t0 = Clock::now();
      for (int k = 0; k < steps; ++k) {
        s.step();
        t.sample(s);
      }
      counted.push_back(1e6 * since(t0) / steps);
      t0 = Clock::now();
      for (int k = 0; k < steps; ++k) {
        s.step();
        t4.sample(s);
      }
      counted4.push_back(1e6 * since(t0) / steps);
    }
    for (auto* v : {&bare, &counted, &counted4}) std::sort(v->begin(), v->end());
    std::printf("  %s, %zu elements: FE step %.1f us (min; median %.1f); counting every step %.1f us (+%.1f %%, "
                "medians +%.1f %%, %.1f ns per element and sample), every 4th step %.1f us (+%.1f %%, medians +%.1f %%)\n",
                name, elements, bare[0], bare[3], counted[0], 100.0 * (counted[0] - bare[0]) / bare[0],
                100.0 * (counted[3] - bare[3]) / bare[3], 1e3 * (counted[0] - bare[0]) / static_cast<double>(elements),
                counted4[0], 100.0 * (counted4[0] - bare[0]) / bare[0], 100.0 * (counted4[3] - bare[3]) / bare[3]);
    std::printf("csv:fatigue_cost,%s,%zu,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f\n", name, elements, bare[0], counted[0],
                counted4[0], bare[3], counted[3], counted4[3]);
  }
}
}  // namespace

// bench_fe [NAME...]: every benchmark, or those named (hammer, threads,
// hex8, bar, axi4, bar_impact, axi_bar_impact, calculix), in this order.
// The Ø20 mm bar impact's two bodies (piston 0.2 m at 8 m/s, tool 0.8 m)
// meshed at h, without contact: both codes step the same two free bodies,
// element and nodal work only.
fe::Model bar_impact_bodies(double h) {
  fe::RevolutionMeshOptions t, p;
  t.element_size = p.element_size = h;
  t.part = 2, t.z0 = -0.8;
  p.part = 1, p.z0 = 1e-4, p.node_offset = 1000000, p.element_offset = 1000000, p.set_offset = 10;
  return fe::parse_deck("*KEYWORD\n" + fe::mesh_revolution({{0.8, 0.01, 0}}, t).keyword_text +
                            fe::mesh_revolution({{0.2, 0.01, 0}}, p).keyword_text + materials(0.3) +
                            "*INITIAL_VELOCITY_GENERATION\n1,2,0,0,0,-8\n0,0,0,0,0,0\n",
                        "bodies.k");
}

// CalculiX's input for model m as C3D8R (LS-DYNA's hex node order is
// CalculiX's), explicit over `duration`, the piston's velocities printed
// once at the end.
void write_ccx_input(const fe::Model& m, double dt, double duration, const std::string& path) {
  std::ofstream o(path);
  o.precision(10);  // CalculiX reads fixed-width fields: 17 digits overflow them
  o << "*HEADING\nbar impact bodies\n*NODE, NSET=NALL\n";
  for (size_t i = 0; i < m.x0.size(); ++i) o << i + 1 << ", " << m.x0[i].x() << ", " << m.x0[i].y() << ", " << m.x0[i].z() << "\n";
  o << "*ELEMENT, TYPE=C3D8R, ELSET=EALL\n";
  for (size_t e = 0; e < m.solids.size(); ++e) {
    o << e + 1;
    for (int a = 0; a < 8; ++a) o << ", " << m.solids[e].n[a] + 1;
    o << "\n";
  }
  o << "*NSET, NSET=PISTON\n";
  int k = 0;
  for (size_t i = 0; i < m.x0.size(); ++i)
    if (m.node_ids[i] >= 1000000) o << i + 1 << (++k % 8 == 0 ? ",\n" : ", ");
  o << "\n*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850.\n";
  o << "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*INITIAL CONDITIONS, TYPE=VELOCITY\nPISTON, 3, -8.0\n";
  // *DYNAMIC, EXPLICIT with CalculiX's own stable increment (DIRECT and
  // NLGEOM made ccx 2.20 iterate at t = 0 without advancing, tried).
  o << "*STEP, INC=10000000\n*DYNAMIC, EXPLICIT\n" << dt << ", " << duration << "\n";
  o << "*NODE PRINT, NSET=PISTON, FREQUENCY=10000000\nV\n*END STEP\n";
}

void calculix_comparison() {
  if (std::system("command -v ccx > /dev/null 2>&1") != 0) {
    std::printf("CalculiX (ccx) not found: comparison skipped (Debian: calculix-ccx)\ncsv:calculix,skipped\n");
    return;
  }
  fe::Model m = bar_impact_bodies(0.0025);
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  fe::Solver s(m, dt);
  const double ours = time_in_slices(s, 200, m.solids.size()).fastest;
  // CalculiX: two runs of different length; the difference removes its
  // start-up (reading, structure of the matrix, masses), leaving the increments.
  char dir_template[] = "/tmp/pcs_ccx_XXXXXX";
  if (!mkdtemp(dir_template)) {
    std::printf("no temporary folder for CalculiX's files: comparison skipped\ncsv:calculix,failed\n");
    return;
  }
  const std::string dir = dir_template;
  double wall[2] = {0, 0}, ccx_dt = 0.0;
  long increments[2] = {0, 0};
  const int ours_steps[2] = {20, 120};
  for (int r = 0; r < 2; ++r) {
    const double duration = ours_steps[r] * dt;
    write_ccx_input(m, dt, duration, dir + "/run" + std::to_string(r) + ".inp");
    const std::string cmd = "cd " + dir + " && OMP_NUM_THREADS=1 CCX_NPROC_RESULTS=1 CCX_NPROC_EQUATION_SOLVER=1 ccx -i run" +
                            std::to_string(r) + " > run" + std::to_string(r) + ".log 2>&1";
    auto c0 = Clock::now();
    const int rc = std::system(cmd.c_str());
    wall[r] = since(c0);
    std::ifstream log(dir + "/run" + std::to_string(r) + ".log");
    std::string line;
    while (std::getline(log, line))
      if (const auto at = line.find("SELECTED time increment:"); at != std::string::npos) ccx_dt = std::atof(line.c_str() + at + 24);
    if (rc != 0 || !(ccx_dt > 0.0)) {
      std::printf("CalculiX failed (exit %d; its log: %s/run%d.log): comparison skipped\ncsv:calculix,failed\n", rc,
                  dir.c_str(), r);
      return;
    }
    increments[r] = static_cast<long>(std::ceil(duration / ccx_dt - 1e-9));
  }
  std::filesystem::remove_all(dir);
  const double theirs = 1e9 * (wall[1] - wall[0]) / (static_cast<double>(increments[1] - increments[0]) * m.solids.size());
  std::printf("against CalculiX (C3D8R explicit, one thread each, %zu elements): ours %.1f ns, ccx %.1f ns per "
              "element-cycle, %.1fx; steps %.3g s (ours) and %.3g s (ccx's own stable increment)\n",
              m.solids.size(), ours, theirs, theirs / ours, dt, ccx_dt);
  std::printf("csv:calculix,%zu,%.2f,%.2f,%.2f,%.4g,%.4g\n", m.solids.size(), ours, theirs, theirs / ours, dt, ccx_dt);
}

int main(int argc, char** argv) {
  const std::pair<const char*, void (*)()> all[] = {
      {"hammer", hammer_fe_step_cost}, {"threads", thread_scaling},      {"hex8", element_cycle_cost},
      {"bar", bar_cycle_cost},         {"axi4", axi_cycle_cost},          {"bar_impact", bar_impact_convergence},
      {"axi_bar_impact", axi_bar_impact_convergence}, {"calculix", calculix_comparison}, {"fatigue", fatigue_cost}, {"tet4", tet4_cycle_cost}};
  for (int i = 1; i < argc; ++i) {
    bool known = false;
    for (const auto& [name, run] : all) known |= std::string(argv[i]) == name;
    if (known) continue;
    if (std::string(argv[i]) == "--version") return std::printf("%s\n", config::version_line("bench_fe").c_str()), 0;
    const bool help = std::string(argv[i]) == "-h" || std::string(argv[i]) == "--help";
    std::fprintf(help ? stdout : stderr, "%susage: bench_fe [NAME ...]   the benchmarks named (default every one):",
                 help ? "" : ("bench_fe: unknown benchmark '" + std::string(argv[i]) + "'\n").c_str());
    for (const auto& [name, run] : all) std::fprintf(help ? stdout : stderr, " %s", name);
    std::fprintf(help ? stdout : stderr, "\n");
    return help ? 0 : 2;
  }
  for (const auto& [name, run] : all) {
    bool wanted = argc < 2;
    for (int i = 1; i < argc; ++i) wanted |= std::string(argv[i]) == name;
    if (wanted) run();
  }
  return 0;
}
