#include "loads/mechanical_load.hpp"

namespace fe {

MechanicalLoad::MechanicalLoad(const Model& model, const config::PortTable& table) : model_(model) {
  for (const auto& port : table.ports) {
    if (port.type != config::PortType::Mechanic) continue;
    const LoadingSet* ls = nullptr;
    for (const auto& l : model.loading_sets)
      if (l.port_id == port.id && l.force) ls = &l;
    if (!ls)
      throw config::InputError(port.where, "mechanical port " + std::to_string(port.id) + " (" + port.label +
                                               ") has no *USER_LOADING_SET with LTYPE FORCE in " + model.source);
    std::vector<int> nodes;
    for (int id : model.node_sets.at(ls->segment_set)) nodes.push_back(model.index_of(id, ls->where));
    if (nodes.empty()) throw config::InputError(ls->where, "node set of mechanical port " + port.label + " is empty");
    ports_.push_back(port.id);
    nodes_.push_back(nodes);
  }
  force_.assign(ports_.size(), 0.0);
}

int MechanicalLoad::slot_of_port(int port_id) const {
  for (size_t i = 0; i < ports_.size(); ++i)
    if (ports_[i] == port_id) return static_cast<int>(i);
  return -1;
}

void MechanicalLoad::apply(double, const std::vector<Vec3>&, const std::vector<Vec3>&, std::vector<Vec3>& f_ext) {
  for (size_t i = 0; i < ports_.size(); ++i) {
    const double share = force_[i] / static_cast<double>(nodes_[i].size());
    for (int n : nodes_[i]) f_ext[static_cast<size_t>(n)][model_.symmetry_axis] += share;
  }
}

double MechanicalLoad::displacement(int slot, const std::vector<Vec3>& x) const {
  double u = 0;
  for (int n : nodes_[static_cast<size_t>(slot)])
    u += x[static_cast<size_t>(n)][model_.symmetry_axis] - model_.x0[static_cast<size_t>(n)][model_.symmetry_axis];
  return u / static_cast<double>(nodes_[static_cast<size_t>(slot)].size());
}

double MechanicalLoad::velocity(int slot, const std::vector<Vec3>& v) const {
  double s = 0;
  for (int n : nodes_[static_cast<size_t>(slot)]) s += v[static_cast<size_t>(n)][model_.symmetry_axis];
  return s / static_cast<double>(nodes_[static_cast<size_t>(slot)].size());
}

}  // namespace fe
