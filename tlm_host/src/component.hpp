// The component interface of the TLM host. Life cycle, as in Hopsan:
// configure (parameters) → initialize (time step known) → simulate_one_step
// (once per step, in the loop order signal → C → Q) → finalize.
#pragma once

#include <functional>
#include <map>
#include <set>
#include <memory>
#include <string>
#include <vector>

#include "config/checkpoint.hpp"
#include "config/keyword_reader.hpp"
#include "node.hpp"

namespace tlm {

enum class Kind { Signal, C, Q };

struct Port {
  std::string name;
  Kind side = Kind::C;  // which side of the node this port is on
  HydraulicNode* node = nullptr;
  bool mechanical = false;  // a translational port (NodeMechanic), else hydraulic
};

// A signal (a position, a velocity, ...) one component offers and others
// read: outputs point at the owner's variable; an input is bound to an output
// by *CONNECT and reads it through `source`. Values are read as they are
// when the reader runs (loop order signal → C → Q, components in file order).
struct SignalPort {
  std::string name;
  bool output = false;
  double* value = nullptr;          // output: the owner's variable
  const double** source = nullptr;  // input: where the binding is stored
  bool optional = false;            // input: may stay unconnected (reads its default)
};

// A value to log each step: a name below the component and where to read it.
struct LogVariable {
  std::string name;
  std::string unit;
  const double* value;
};

// Parameters as written in the model (name=value), with their location.
// Every parameter must be used by the component; a leftover one is an error,
// so a typo is not silently ignored.
// A parameter's unit, declared where the component reads it: SI ("Pa",
// "m³/s", "N·s/m"), "1" for a pure number, "0/1" for a switch, "signal" for
// a value in its signal's own unit. Only a string literal converts to it, so
// a fallback of 0 cannot be taken for a unit.
struct Unit {
  template <std::size_t N>
  constexpr Unit(const char (&s)[N]) : text(s) {}  // NOLINT: implicit on purpose
  const char* text;
};

class ParameterSet {
 public:
  void set(const std::string& key, const std::string& value, const config::SourceLocation& where);
  bool has(const std::string& key) const {
    asked_.emplace(key, "");
    return values_.count(key) != 0;
  }
  // A real parameter in SI units; its unit is listed with it when a
  // parameter given is not the component's, and must be the plausibility
  // table's where that table knows the name (component.cpp; a different one
  // is a programming error: std::logic_error).
  double real(const std::string& key, double fallback, Unit unit);
  double real(const std::string& key, Unit unit);  // required
  double positive(const std::string& key, double fallback, Unit unit);
  // The number given for `key`, as a tool outside the component reads it
  // (tlm_fit's start value): no unit, not marked as read. Throws
  // config::InputError if it is absent or not a number.
  double given_number(const std::string& key) const;
  // A whole number from lo to hi (a port count, ...): 2.5 or 5.8e9 is refused.
  int integer(const std::string& key, int fallback, int lo, int hi);
  std::string text(const std::string& key, const std::string& fallback);
  void check_all_used(const std::string& component) const;
  const config::SourceLocation& where() const { return where_; }
  void set_where(const config::SourceLocation& w) { where_ = w; }

 private:
  struct Entry {
    std::string value;
    config::SourceLocation where;
    bool used = false;
  };
  std::map<std::string, Entry> values_;
  config::SourceLocation where_;
  // Every key the component asked for while it configured itself: its
  // parameters, listed when one given is not among them.
  mutable std::map<std::string, std::string> asked_;  // name → declared unit ("1" for a count, "" for a text)
};

class Component {
 public:
  explicit Component(std::string name) : name_(std::move(name)) {}
  virtual ~Component() = default;
  virtual Kind kind() const = 0;
  virtual const char* type_name() const = 0;
  // Read parameters; create ports. Throws config::InputError on bad values.
  virtual void configure(ParameterSet& p) = 0;
  // The time step is known and every port is connected.
  virtual void initialize(double dt) = 0;
  // Advance from t to t + dt.
  virtual void simulate_one_step(double t) = 0;
  virtual void finalize() {}
  // Save or restore everything simulate_one_step changes (checkpoint and
  // restart, config/checkpoint.hpp); called after initialize(). Pure, so a
  // new component cannot forget its state: a stateless one says so with an
  // empty body.
  virtual void state(config::StateIO& io) = 0;
  virtual void log_variables(std::vector<LogVariable>&) {}

  const std::string& name() const { return name_; }
  std::vector<Port>& ports() { return ports_; }
  Port* port(const std::string& name);
  std::vector<SignalPort>& signals() { return signals_; }
  SignalPort* signal(const std::string& name);
  // Largest stable time step of this component (infinity if it has no
  // limit), and what limits it; the host warns before a run that exceeds it.
  virtual double stable_step(std::string* /*why*/) const { return 1e300; }
  // True if a step waits on another process (an FMU's fmi2DoStep): several
  // such Q components are stepped concurrently (PeerGroup).
  virtual bool waits_on_peer() const { return false; }
  // Such a component's step in two halves, for an importer that steps its
  // peers one after the other (PeerGroup, Stepping::Sequential): give the
  // peer this step's inputs; simulate_one_step then steps without giving
  // them again.
  virtual void send_peer_inputs() {}
  // Why the host's time step `dt` cannot drive this component ("" if it can):
  // checked before step 1, so a mismatch is refused rather than simulated.
  virtual std::string step_mismatch(double /*dt*/) const { return ""; }
  // The highest pressure (Pa absolute) this component imposes or starts at:
  // a pressure source its set value, a volume its start pressure. A
  // component that can drive a node to any pressure (a flow source, a pump,
  // an FMU) returns +inf: the run-quality guard then has no upper bound.
  virtual double source_pressure() const { return 0.0; }
  // The clock at the run's first row (0 but for a Hopsan model starting
  // before 0), set before initialize(): what a source reads at its start.
  void set_start_time(double t0) { start_time_ = t0; }

 protected:
  double start_time_ = 0.0;
  Port& add_port(const std::string& port_name, Kind side, bool mechanical = false);
  void add_signal_output(const std::string& signal_name, double* value);
  // `source` is set to the bound output; an optional input starts at `fallback`.
  void add_signal_input(const std::string& signal_name, const double** source, const double* fallback = nullptr);
  std::string name_;
  std::vector<Port> ports_;
  std::vector<SignalPort> signals_;
};

using ComponentFactory = std::function<std::unique_ptr<Component>(const std::string& name)>;
// Registered component types, by type name (e.g. "HydraulicVolumeC").
const std::map<std::string, ComponentFactory>& component_types();

}  // namespace tlm
