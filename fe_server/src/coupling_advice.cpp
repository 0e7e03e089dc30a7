#include "coupling_advice.hpp"

#include <cmath>
#include <set>
#include <sstream>

#include "cavity_load.hpp"

namespace fe {

std::vector<PortStability> coupling_stability(const Model& model, const config::PortTable& table, double beta) {
  std::vector<PortStability> out;
  const double T = table.dt, dt_fe = table.dt / table.subcycles;
  for (const auto& ls : model.loading_sets) {
    if (ls.force) continue;
    const config::Port* port = table.find_port(ls.port_id);
    if (!port) continue;
    PortStability s;
    s.label = port->label;
    std::set<int> nodes;
    Vec3 area = Vec3::Zero();
    for (const auto& seg : model.segment_sets.at(ls.segment_set)) {
      area += segment_area_vector(seg, model.x0);
      for (int k = 0; k < 4; ++k) nodes.insert(seg.n[k]);
    }
    s.area = area.norm();
    for (const auto& b : model.rigid_bodies)
      for (int n : b.nodes)
        if (nodes.count(n) && b.mass > s.mass) s.mass = b.mass;
    if (s.mass == 0.0)
      for (int n : nodes) s.mass += model.mass[static_cast<size_t>(n)];
    if (s.mass > 0.0) {
      s.v_min_pressure = beta * s.area * s.area * T * T / s.mass;
      s.v_min_tlm = beta * s.area * s.area * T * dt_fe / (2.0 * s.mass);
    }
    out.push_back(s);
  }
  return out;
}

std::string coupling_stability_text(const std::vector<PortStability>& ports, const config::PortTable& table,
                                    double beta) {
  std::ostringstream o;
  const bool tlm = table.mode == config::CouplingMode::Tlm;
  for (const auto& p : ports) {
    o << "fe_server: coupling estimate, port " << p.label << " (" << p.mass << " kg behind " << p.area * 1e4
      << " cm²): " << (tlm ? "TLM" : "pressure") << " coupling at " << table.dt << " s needs a chamber of at least "
      << (tlm ? p.v_min_tlm : p.v_min_pressure) * 1e6 << " cm³ at β = " << beta / 1e9 << " GPa";
    o << " (" << (tlm ? "pressure" : "TLM") << " coupling: " << (tlm ? p.v_min_pressure : p.v_min_tlm) * 1e6
      << " cm³)\n";
  }
  return o.str();
}

}  // namespace fe
