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
    std::vector<double> weights;
    if (ls->body) {
      nodes = ls->body_nodes;
      double total = 0.0;
      for (int n : nodes) total += model.mass[static_cast<size_t>(n)];
      if (!(total > 0.0)) throw config::InputError(ls->where, "the parts of mechanical port " + port.label + " have no mass");
      for (int n : nodes) weights.push_back(model.mass[static_cast<size_t>(n)] / total);
    } else {
      for (int id : model.node_sets.at(ls->segment_set)) nodes.push_back(model.index_of(id, ls->where));
      if (nodes.empty()) throw config::InputError(ls->where, "node set of mechanical port " + port.label + " is empty");
      weights.assign(nodes.size(), 1.0 / static_cast<double>(nodes.size()));
    }
    ports_.push_back(port.id);
    nodes_.push_back(nodes);
    weights_.push_back(weights);
  }
  force_.assign(ports_.size(), 0.0);
}

int MechanicalLoad::slot_of_port(int port_id) const {
  for (size_t i = 0; i < ports_.size(); ++i)
    if (ports_[i] == port_id) return static_cast<int>(i);
  return -1;
}

void MechanicalLoad::apply(double, const std::vector<Vec3>&, const std::vector<Vec3>&, std::vector<Vec3>& f_ext) {
  for (size_t i = 0; i < ports_.size(); ++i)
    for (size_t k = 0; k < nodes_[i].size(); ++k)
      f_ext[static_cast<size_t>(nodes_[i][k])][model_.symmetry_axis] += force_[i] * weights_[i][k];
}

double MechanicalLoad::displacement(int slot, const std::vector<Vec3>& x) const {
  const size_t i = static_cast<size_t>(slot);
  const int a = model_.symmetry_axis;
  double u = 0;
  for (size_t k = 0; k < nodes_[i].size(); ++k) {
    const size_t n = static_cast<size_t>(nodes_[i][k]);
    u += weights_[i][k] * (x[n][a] - model_.x0[n][a]);
  }
  return u;
}

double MechanicalLoad::velocity(int slot, const std::vector<Vec3>& v) const {
  const size_t i = static_cast<size_t>(slot);
  double s = 0;
  for (size_t k = 0; k < nodes_[i].size(); ++k)
    s += weights_[i][k] * v[static_cast<size_t>(nodes_[i][k])][model_.symmetry_axis];
  return s;
}

}  // namespace fe
