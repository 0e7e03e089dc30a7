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

#include <string>

namespace tlm {

struct HydraulicNode {
  double p = 0.0;   // Pa
  double q = 0.0;   // m³/s, from the Q component into the C component
  double c = 0.0;   // Pa
  double Zc = 0.0;  // Pa·s/m³
  std::string name; // "<C component>.<port>"
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

}  // namespace tlm
