// The deck's unit system, inferred (issue 32: a deck with E in MPa and ρ in
// kg/m³ ran one step longer than its end time and exited 0).
//
// LS-DYNA has no units: any consistent set works, and the deck does not say
// which. The materials do. For each consistent system LS-DYNA users use
// (m–kg–s, mm–t–s, mm–kg–ms, mm–g–ms, cm–g–µs, m–t–s, in–lbf·s²/in–s) a
// deformable part's bar wave speed √(E/ρ) and its density, converted to SI,
// must be those of a solid (wave speed 20 to 20 000 m/s, density 1 to
// 25 000 kg/m³: foams and rubbers to tungsten), and the model's size that of
// a machine part (1 mm to 100 m across). A deck that fits no system is
// refused naming the part and its numbers; one that fits only systems other
// than SI must come with a port table whose scale factors convert to them.
#pragma once

#include <string>
#include <vector>

#include "config/port_table.hpp"
#include "model/model.hpp"

namespace fe {

struct UnitSystem {
  const char* name;              // "m, kg, s"
  double length, mass, time;     // the units in SI: m, kg, s
  double stress() const { return mass / (length * time * time); }  // Pa
  double force() const { return mass * length / (time * time); }   // N
};

// The systems the deck's deformable parts and size fit, in the order above
// (empty: none; `why` then says which part fails and how).
std::vector<UnitSystem> deck_unit_systems(const Model& m, std::string* why);

// Refuses (config::InputError at the first material's line) a deck that fits
// no system. With port tables, also one whose scale factors fit none of the
// systems the deck does (a pressure in Pa sent to a deck in MPa: scale 1e-6).
void check_units(const Model& m, const std::vector<config::PortTable>& tables);

}  // namespace fe
