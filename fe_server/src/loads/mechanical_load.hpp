// Mechanical co-simulation ports: the host's force along the deck's axis on
// a node set (*USER_LOADING_SET SID, FORCE, PORT), shared equally by the
// set's nodes (on a rigid body the whole body feels it), or on the parts of a
// part set (LTYPE BODY), shared in proportion to the nodal masses like a body
// force. The port reports the same weighted mean of the nodes' displacement
// and velocity along the axis (for BODY the centre of mass's).
#pragma once

#include <vector>

#include "config/port_table.hpp"
#include "loads/user_load.hpp"

namespace fe {

class MechanicalLoad : public UserLoad {
 public:
  MechanicalLoad(const Model& model, const config::PortTable& table);
  int slot_of_port(int port_id) const;  // -1 if the port is not mechanical
  void set_force(int slot, double F) { force_[static_cast<size_t>(slot)] = F; }
  double force(int slot) const { return force_[static_cast<size_t>(slot)]; }
  void apply(double t, const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& f_ext) override;
  bool loaded_nodes(std::vector<int>& nodes) const override {
    for (const auto& set : nodes_) nodes.insert(nodes.end(), set.begin(), set.end());
    return true;
  }
  double displacement(int slot, const std::vector<Vec3>& x) const;
  double velocity(int slot, const std::vector<Vec3>& v) const;
  void state(config::StateIO& io) override { io.array("mechanical force", force_); }  // the host's last forces

 private:
  const Model& model_;
  std::vector<int> ports_;
  std::vector<std::vector<int>> nodes_;
  std::vector<std::vector<double>> weights_;  // each port's weights sum to 1
  std::vector<double> force_;
};

// Several hooks called in turn at the user-load stage.
class UserLoads : public UserLoad {
 public:
  void add(UserLoad* l) { loads_.push_back(l); }
  void apply(double t, const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& f_ext) override {
    for (UserLoad* l : loads_) l->apply(t, x, v, f_ext);
  }
  bool loaded_nodes(std::vector<int>& nodes) const override {
    bool all_declared = true;
    for (UserLoad* l : loads_) all_declared = l->loaded_nodes(nodes) && all_declared;
    return all_declared;
  }
  // Each load solves against the same prediction: exact while at most one of
  // them has implicit ports on a given body (the cavity load holds them all).
  void apply_implicit(const Mobility& m, const std::vector<Vec3>& v_old, const std::vector<Vec3>& v_pred,
                      std::vector<NodalForce>& out) override {
    for (UserLoad* l : loads_) l->apply_implicit(m, v_old, v_pred, out);
  }
  void state(config::StateIO& io) override {
    io.expect("loads", loads_.size(), "the number of user loads");
    for (UserLoad* l : loads_) l->state(io);
  }

 private:
  std::vector<UserLoad*> loads_;
};

}  // namespace fe
