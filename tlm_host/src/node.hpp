// A hydraulic node joins exactly one C-type port and one Q-type port
// (transmission-line modelling, as in Hopsan: Krus, Jansson, Palmberg 1990).
//
//   c, Zc  written by the C side (wave variable and characteristic impedance)
//   p, q   written by the Q side
//
// Sign convention: q is the volume flow from the Q component into the C
// component (positive into the capacitive element). The C side's boundary
// characteristic is then  p = c + Zc·q: flow into a capacitance raises its
// pressure.
#pragma once

#include <algorithm>
#include <string>

namespace tlm {

struct HydraulicNode {
  double p = 0.0;   // Pa
  double q = 0.0;   // m³/s, from the Q component into the C component
  double c = 0.0;   // Pa
  double Zc = 0.0;  // Pa·s/m³
  std::string name; // "<C component>.<port>"
  // A mechanical (translational) node, Hopsan's NodeMechanic, uses the same
  // slots: p is the force F (N), q the velocity v (m/s), c and Zc the wave
  // variable (N) and impedance (N·s/m) with F = c + Zc·v; besides them the
  // position x (m) and the equivalent mass me (kg) the Q side moves, both
  // written by the Q side (me starts at 1 kg, Hopsan's start value). x and
  // v are counted in the Q component's direction at that port, as Hopsan
  // counts them.
  bool mechanical = false;
  double x = 0.0;
  double me = 0.0;
};

// A two-port Q component passing flow q from node 1 to node 2: node 1's C
// element loses q, node 2's gains it, and each node's pressure follows its
// characteristic p = c + Zc·q.
inline void set_through_flow(HydraulicNode& n1, HydraulicNode& n2, double q) {
  n1.q = -q;
  n2.q = q;
  n1.p = n1.c + n1.Zc * n1.q;
  n2.p = n2.c + n2.Zc * n2.q;
}

// Hopsan's orifices' cavitation check (its HydraulicTurbulentOrifice and
// HydraulicLaminarOrifice): where the flow would leave a port's pressure
// below zero, the flow is solved again as if that node held 0 Pa (c = 0,
// Zc = 0 there), and no pressure below zero is written. For components
// mapped from Hopsan models only: in our own models the volumes hold the
// vapour pressure and conserve oil instead. `flow(c1, c2, Zc1, Zc2)` is the
// component's flow from node 1 to node 2; returns the flow written.
template <class Flow>
double set_through_flow_hopsan(HydraulicNode& n1, HydraulicNode& n2, const Flow& flow) {
  double c1 = n1.c, c2 = n2.c, Z1 = n1.Zc, Z2 = n2.Zc;
  double q = flow(c1, c2, Z1, Z2);
  double p1 = c1 + -q * Z1, p2 = c2 + q * Z2;
  if (p1 < 0.0 || p2 < 0.0) {
    if (p1 < 0.0) c1 = 0.0, Z1 = 0.0;
    if (p2 < 0.0) c2 = 0.0, Z2 = 0.0;
    q = flow(c1, c2, Z1, Z2);
    p1 = std::max(c1 + -q * Z1, 0.0);
    p2 = std::max(c2 + q * Z2, 0.0);
  }
  n1.q = -q, n1.p = p1;
  n2.q = q, n2.p = p2;
  return q;
}

}  // namespace tlm
