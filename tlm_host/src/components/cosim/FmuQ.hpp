// An FMI 2.0 co-simulation FMU as a Q-type component. Its hydraulic ports
// come from the FMU's variable names: a port L has the output L.q (flow out
// of the FMU into the node) and either the input L.p (pressure coupling) or
// the inputs L.c and L.Zc (TLM coupling).
//
// Pressure coupling (one step delay): the FMU is sent p = c + Zc·q_prev,
// returns the flow q it produced over the step, and the node gets q and
// p = c + Zc·q. TLM coupling: the FMU is sent c and Zc and solves
// p = c + Zc·q itself, exactly like a Q component. Each hydraulic port's
// node pressure after the step is offered as the signal "<label>.p_node".
#pragma once

#include <memory>

#include "component.hpp"
#include "fmu_importer.hpp"

namespace tlm {

class FmuQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "FmuQ"; }
  // Moves oil by force or displacement: a node's pressure has no bound from the sources.
  double source_pressure() const override { return 1e300; }
  // The last flows and outputs; the FMU's own session state is fe_server's
  // checkpoint, taken first (System::checkpoint).
  void state(config::StateIO& io) override;
  // A restarted run: the FMU resumes its session after `step` coupling
  // steps. Before initialize().
  void set_resume_step(long step) { resume_step_ = step; }
  std::string checkpoint() { return fmu_->checkpoint(); }
  void confirm_resume() { fmu_->confirm_resume(); }
  // Its fe_server got a stop signal and asks for a checkpoint.
  bool server_stopping() { return fmu_->stop_requested(); }
  void configure(ParameterSet& prm) override;
  void initialize(double dt) override;
  void simulate_one_step(double t) override;
  void finalize() override;
  void log_variables(std::vector<LogVariable>& out) override;
  bool waits_on_peer() const override { return true; }
  void send_peer_inputs() override {
    send_inputs();
    inputs_sent_ = true;
  }
  // Our FMUs exchange once per coupling step (their DefaultExperiment
  // stepSize, the port table's timestep): a host stepping at another step
  // would hold the FE side's inputs over many coupling steps while its TLM
  // lines assume the host's delay (the one-DOF scene at a host step of 1 ms
  // and a coupling step of 10 µs ended 1.5e19 m away, exit 0).
  std::string step_mismatch(double dt) const override;

 private:
  struct HydraulicPort {
    size_t port = 0;  // index into ports_
    bool tlm = false;
    bool zc_check = false;  // pressure mode with an input L.Zc: the node's Zc for fe_server's stability check
    unsigned vr_p = 0, vr_c = 0, vr_Zc = 0, vr_q = 0;
    double q = 0.0;
    double p_node = 0.0;  // the node's pressure after the step (signal "<label>.p_node")
  };
  struct Output {
    std::string name;
    unsigned vr = 0;
    double value = 0.0;
    std::string unit;  // the model description's, logged with the series
  };
  // Inputs for the coming step from each port's node (pressure or c, Zc).
  void send_inputs();
  std::shared_ptr<FmuArchive> archive_;
  std::unique_ptr<FmuInstance> fmu_;
  std::vector<HydraulicPort> hports_;
  // Hopsan (FMIWrapperQ): an output one of the ports' node slots reads; a
  // name as Hopsan makes it; the portspecs checked against the FMU.
  bool port_variable(const std::string& name) const;
  static std::string hopsan_name(std::string name);
  void check_hopsan_portspecs(const std::string& specs, const config::SourceLocation& where) const;
  std::vector<Output> outputs_;
  struct SignalInput {
    unsigned vr = 0;
    const double* value = nullptr;
  };
  std::vector<SignalInput> signal_inputs_;  // FMU inputs outside the hydraulic ports (e.g. a force)
  std::string server_, token_;
  double dt_ = 0.0;
  bool verbose_ = false;
  long resume_step_ = -1;  // -1: a fresh session
  bool inputs_sent_ = false;  // send_peer_inputs() gave this step's inputs
  std::vector<unsigned> in_vr_;  // send_inputs(): one fmi2SetReal for them all
  std::vector<double> in_value_;
};

}  // namespace tlm
