// Three-way spool valve (Q-type): metering edges P→A and A→T, areas
// tabulated against the spool position x (signal input), e.g.
// area_PA = "0:0; 0.004:0; 0.008:3.14e-4".
//
// Both edges meet at port A, so they are solved together. For a trial p_A
// each edge has the exact TLM orifice flow against its other node,
//   q_PA(p_A) = orifice(c_P, Zc_P → p_A),   q_AT(p_A) = orifice(p_A → c_T, Zc_T),
// and node A must satisfy  r(p_A) = c_A + Zc_A·(q_PA − q_AT) − p_A = 0.
// r decreases strictly in p_A and changes sign between min(c) and max(c),
// so GSL's Brent solver finds the root in that bracket.
#pragma once

#include <gsl/gsl_roots.h>

#include <memory>

#include "component.hpp"
#include "table.hpp"

namespace tlm {

class SpoolValveQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "SpoolValveQ"; }
  void state(config::StateIO& io) override {
    for (double* s : {&K_PA_, &K_AT_, &q_PA_, &q_AT_}) io.value("spool valve", *s);
    io.value("iterations", iterations_);
  }
  void configure(ParameterSet& prm) override;
  void initialize(double) override {
    solver_.reset(gsl_root_fsolver_alloc(gsl_root_fsolver_brent));  // once, not on every step
  }
  void simulate_one_step(double) override;
  void log_variables(std::vector<LogVariable>& out) override;
  // Residual of node A for a trial p_A (public for the root finder's callback).
  double residual(double pA) const;

 private:
  double Cd_ = 0, rho_ = 0;
  Table area_PA_, area_AT_;
  const double* x_ = nullptr;
  double K_PA_ = 0, K_AT_ = 0, q_PA_ = 0, q_AT_ = 0;
  long iterations_ = 0;
  std::unique_ptr<gsl_root_fsolver, void (*)(gsl_root_fsolver*)> solver_{nullptr, gsl_root_fsolver_free};
};

}  // namespace tlm
