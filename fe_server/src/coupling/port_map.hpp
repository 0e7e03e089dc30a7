// The port table's variables on the model (fe_server's side of one FMU's
// ports): which load each input sets and what each output measures, and
// the coupling guard on the impedances the host sends. CouplingServer
// drives one per client; follow_session (the MPI ranks) drives the same.
#pragma once

#include <string>
#include <vector>

#include "config/port_table.hpp"
#include "coupling/coupling_advice.hpp"
#include "loads/cavity_load.hpp"
#include "loads/mechanical_load.hpp"
#include "solver/solver.hpp"

namespace fe {

// Maps the table's variables to the model: which load each input sets and
// what each output measures. Throws config::InputError for a variable the
// model cannot serve.
//
// One coupling step: apply_inputs (pressure, or wave and impedance), then
// after each of the k FE sub-steps accumulate(); measure_outputs returns flow
// and pressure averaged over the sub-steps (so the oil volume exchanged is
// the volume the surface swept in the coupling step) and displacement and
// velocity at its end.
class PortMap {
 public:
  PortMap(const config::PortTable& table, CavityPressureLoad& load, MechanicalLoad& mech);
  void apply_inputs(const std::vector<double>& in);
  void accumulate(const Solver& s);
  void measure_outputs(const Solver& s, std::vector<double>& out);
  // The coupling guard: at coupling step T the FE side sees the host's
  // chamber as the stiffness A²·Zc/T on the port's mass m, so
  // ω·T = A·sqrt(Zc·T/m) (coupling_advice.hpp). check_coupling() returns why
  // the impedances just applied put a port beyond its limit ("" if none
  // does, or if `allow`), looking again only when a port's Zc changed: a TLM
  // port beyond max_tlm_omega_t() (accuracy), a pressure port whose table
  // sends the host's Zc beyond kMaxPressureOmegaT (stability).
  void set_coupling_guard(const std::vector<PortStability>& ports, double T, bool allow);
  std::string check_coupling();

 private:
  const config::PortTable& table_;
  CavityPressureLoad& load_;
  MechanicalLoad& mech_;
  std::vector<int> in_slot_, out_slot_;  // hydraulic slot, or mechanical slot when *_mech_ is set
  std::vector<char> in_mech_, out_mech_;
  std::vector<double> wave_, impedance_;         // per slot, TLM mode
  std::vector<char> tlm_;                        // per slot: wave/impedance given this step
  std::vector<char> zc_sent_;                    // per slot: the table sends the host's Zc (pressure mode: checked)
  std::vector<double> flow_sum_, pressure_sum_;  // per slot, over the sub-steps
  double substeps_ = 0.0;  // the FE steps of this coupling step, each weighted by its share of the start's step
  struct Guard {
    std::string label;
    double mass = 0.0, area = 0.0, checked_zc = -1.0;
  };
  std::vector<Guard> guard_;  // per slot (mass 0: not guarded)
  double guard_T_ = 0.0;
};

}  // namespace fe
