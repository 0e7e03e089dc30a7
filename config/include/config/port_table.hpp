// The typed port table: what the co-simulation exchanges, read from the
// keyword-style port configuration (ports.cfg). It is described once here;
// the FMU's variables and value references (fmu_variables), the HELLO hash
// and the FE server's port map all derive from it.
//
//   $FMU_SETTINGS        key, value   (model, description, server, timestep, mode, subcycles,
//                                      timeout, host_convention)
//   $FMU_HOPSAN_PORTS    id, label, type          (Hydraulic | Mechanic | Signal)
//   $FMU_HOPSAN_SEND     port id, quantity, scale (host → FE)
//   $FMU_HOPSAN_RECEIVE  port id, quantity, scale (FE → host)
//
// Scale factors: the FMU multiplies every value it sends and receives by its
// scale, so a half or quarter FE model is seen by the host as the whole one.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "config/keyword_reader.hpp"

namespace config {

enum class PortType { Hydraulic, Mechanic, Signal };
enum class Quantity { Pressure, Flow, Wave, Impedance, Displacement, Velocity, Force, Signal };
enum class CouplingMode { Pressure, Tlm };

const char* to_string(PortType t);
const char* to_string(CouplingMode m);
const char* symbol(Quantity q);  // "p", "q", "c", "Zc", "x", "v", "F", "y"
const char* unit(Quantity q);    // SI unit
const char* long_name(Quantity q);

struct Port {
  int id = 0;
  std::string label;
  PortType type = PortType::Hydraulic;
  SourceLocation where;
};

struct Variable {
  int port_id = 0;
  std::string port_label;
  Quantity quantity = Quantity::Pressure;
  double scale = 1.0;
  SourceLocation where;
  std::string name() const { return port_label + "." + symbol(quantity); }
};

struct PortTable {
  std::string source;  // file it was read from
  std::string model_name;
  // What the FMU is, for its modelDescription.xml (not part of the hash);
  // empty: fmugen writes one from the ports.
  std::string description;
  std::string server;  // default HOST:PORT of fe_server
  double dt = 0.0;     // coupling time step, s
  CouplingMode mode = CouplingMode::Pressure;
  int subcycles = 1;     // FE steps per coupling step
  double timeout = 60.0; // per-step receive deadline, s
  // host_convention, hopsan: the FMU's hydraulic ports follow Hopsan's node
  // (FMIWrapperQ reads q, p, T, c, Zc, Qdot per port): TLM mode, and each
  // port offers its pressure p = c + Zc·q, its temperature T and heat flow
  // Qdot besides; outputs carry start values. Part of the hash only when set.
  bool hopsan = false;
  double hopsan_temperature = 293.0;  // K, the oil's (isothermal)
  // Pa, each port's pressure before the first step: the start value Hopsan
  // logs at t = 0 (FMIWrapperQ reads outputs' start values from the model
  // description); Hopsan's own default node pressure unless set.
  double hopsan_start_pressure = 1e5;
  std::vector<Port> ports;
  std::vector<Variable> to_fe;    // host → FE, in wire order
  std::vector<Variable> to_host;  // FE → host, in wire order

  const Port* find_port(int id) const;
  // FNV-1a 64 of the canonical table (model, dt, mode, subcycles, ports,
  // variables with scales); the server address and time-out are not part of
  // it, since they differ between a cluster run and a local one.
  uint64_t hash() const;
  std::string canonical() const;
};

PortTable parse_port_table(const std::string& text, const std::string& name);
PortTable read_port_table(const std::string& path);

// One fe_server session serving several FMUs (one per co-simulated part):
// the tables' ports and variables in one table, in the tables' order. They
// must agree on time step, coupling mode and sub-cycles, and no port id or
// label may appear twice (InputError naming both files otherwise).
PortTable combine_port_tables(const std::vector<PortTable>& tables);

// ---- the FMU's variables, derived from the table (value references too) ----
enum class FmuCausality { Input, Output, Parameter };
enum class FmuType { Real, Integer, String };

struct FmuVariable {
  std::string name;
  unsigned value_reference = 0;
  FmuCausality causality = FmuCausality::Input;
  FmuType type = FmuType::Real;
  std::string start;  // empty: no start attribute
  std::string unit;
  std::string description;
  int wire_index = -1;  // index into to_fe (inputs) or to_host (outputs)
  // Outputs the FMU computes itself (Hopsan convention): p = c + Zc·q from
  // the inputs c, Zc and the output q at these wire indices; or a constant
  // (T, Qdot). `initial` is "exact" when the start value holds before the
  // first step (FMI 2.0 2.2.7), else empty.
  enum class Derived { None, Pressure, Constant } derived = Derived::None;
  int wire_c = -1, wire_zc = -1, wire_q = -1;
  double constant = 0.0;
  std::string initial;
};

// Value references of the fixed parameters; port variables count from 0.
constexpr unsigned kVrServerHost = 1000000;
constexpr unsigned kVrServerPort = 1000001;
constexpr unsigned kVrServerToken = 1000002;
constexpr unsigned kVrTimeout = 1000003;
// FMI 3.0's independent variable, time (its model description only).
constexpr unsigned kVrTime = 1000004;

std::vector<FmuVariable> fmu_variables(const PortTable& table);

// The shortest decimal text that reads back as exactly v (std::to_chars):
// 1e-05, where %.17g gives 1.0000000000000001e-05.
std::string shortest(double v);

// Hopsan's NodeHydraulic in its data order (Flow, Pressure, Temperature,
// WaveVariable, CharImpedance, HeatFlow): the variable of each slot, after
// the port's label and a dot.
inline constexpr const char* kHopsanNodeHydraulic[6] = {"q", "p", "T", "c", "Zc", "Qdot"};

// Hopsan's FMIWrapperQ "portspecs" for an FMU of the Hopsan convention:
// "NodeHydraulic:label,label.q,label.p,label.T,label.c,label.Zc,label.Qdot;..."
// (empty for another table).
std::string hopsan_portspecs(const PortTable& table);

// "pcs-" + 16 hex digits of the hash: the FMU's GUID, tying
// modelDescription.xml to the resources/ports.cfg it was made from.
std::string fmu_guid(const PortTable& table);

}  // namespace config
