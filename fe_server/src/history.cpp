#include "history.hpp"

namespace fe {

History::History(const std::string& path, const Model& model, const config::PortTable* table)
    : writer_(path), model_(model) {
  writer_.set_attribute("producer", "fe_server");
  writer_.set_attribute("deck", model.source);
  writer_.set_attribute("title", model.title);
  writer_.add_series("time", "s");
  if (table) {
    writer_.set_attribute("port_table", table->source);
    for (const auto& v : table->to_fe) writer_.add_series("ports/" + v.name(), config::unit(v.quantity));
    for (const auto& v : table->to_host) writer_.add_series("ports/" + v.name(), config::unit(v.quantity));
  }
  for (int i : model.history_nodes) {
    std::string base = "nodes/" + std::to_string(model.node_ids[static_cast<size_t>(i)]) + "/";
    for (const char* c : {"ux", "uy", "uz"}) writer_.add_series(base + c, "m");
    for (const char* c : {"vx", "vy", "vz"}) writer_.add_series(base + c, "m/s");
  }
  for (const char* e : {"kinetic", "internal", "damping", "external_work", "balance_error"})
    writer_.add_series(std::string("energy/") + e, "J");
  row_.resize(writer_.columns());
}

void History::record(const Solver& s, const std::vector<double>& inputs,
                     const std::vector<double>& outputs) {
  size_t k = 0;
  row_[k++] = s.time();
  for (double v : inputs) row_[k++] = v;
  for (double v : outputs) row_[k++] = v;
  for (int i : model_.history_nodes) {
    const size_t n = static_cast<size_t>(i);
    for (int c = 0; c < 3; ++c) row_[k++] = s.x()[n][c] - model_.x0[n][c];
    for (int c = 0; c < 3; ++c) row_[k++] = s.v()[n][c];
  }
  const Energies& e = s.energies();
  for (double v : {e.kinetic, e.internal, e.damping, e.external_work, e.balance_error}) row_[k++] = v;
  writer_.append(row_);
}

}  // namespace fe
