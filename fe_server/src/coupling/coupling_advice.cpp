#include "coupling/coupling_advice.hpp"

#include <cmath>
#include <set>
#include <sstream>

#include "loads/cavity_load.hpp"

namespace fe {

std::vector<PortStability> coupling_stability(const Model& model, const config::PortTable& table, double beta) {
  std::vector<PortStability> out;
  const double T = table.dt;
  for (const auto& ls : model.loading_sets) {
    if (ls.force) continue;
    const config::Port* port = table.find_port(ls.port_id);
    if (!port) continue;
    PortStability s;
    s.label = port->label;
    s.port_id = ls.port_id;
    std::set<int> nodes;
    Vec3 area = Vec3::Zero();
    for (const auto& seg : model.segment_sets.at(ls.segment_set)) {
      area += segment_area_vector(seg, model.x0);
      for (int k = 0; k < seg.corners(); ++k) nodes.insert(seg.n[k]);
    }
    s.area = area.norm();
    for (const auto& b : model.rigid_bodies)
      for (int n : b.nodes)
        if (nodes.count(n) && b.mass > s.mass) s.mass = b.mass;
    if (s.mass == 0.0)
      for (int n : nodes) s.mass += model.mass[static_cast<size_t>(n)];
    if (s.mass > 0.0) {
      s.v_min_pressure = beta * s.area * s.area * T * T / s.mass;
      // |Δf/f| = e·(ω·T)² ≤ 1 %  ⇔  ω·T ≤ sqrt(0.01/e)  ⇔  V ≥ β·A²·T²·e/(0.01·m).
      s.v_accurate_tlm = s.v_min_pressure * kTlmErrorPerOmegaT2 / 0.01;
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
      << " cm², β = " << beta / 1e9 << " GPa): ";
    if (tlm)
      o << "TLM coupling at " << table.dt << " s is stable for any chamber; a chamber of at least "
        << p.v_accurate_tlm * 1e6 << " cm³ keeps its frequency error below 1 % (pressure coupling would need "
        << p.v_min_pressure * 1e6 << " cm³ to be stable)\n";
    else
      o << "pressure coupling at " << table.dt << " s needs a chamber of at least " << p.v_min_pressure * 1e6
        << " cm³ (ω·T ≤ 1); TLM coupling is stable for any chamber\n";
  }
  return o.str();
}

}  // namespace fe
