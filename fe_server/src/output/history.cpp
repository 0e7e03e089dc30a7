#include "output/history.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "output/ascii_output.hpp"
#include "output/fatigue.hpp"
#include "output/field_output.hpp"

namespace fe {

namespace {

// FE steps between rows for an interval (at least one).
long steps_per_row(double interval, double fe_dt) {
  const double k = std::round(interval / fe_dt);
  return k >= 1.0 ? static_cast<long>(std::min(k, 1e15)) : 1;
}

}  // namespace

History::History(const std::string& path, const Model& model, const config::PortTable* table, double fe_dt,
                 double default_interval, bool resume)
    : writer_(path, 4096, 1.0, resume),
      model_(model),
      // 2D axisymmetric: a section's components along the axis only
      section_components_(model.symmetry_axis == 1 ? std::vector<int>{1} : std::vector<int>{0, 1, 2}) {
  writer_.set_attribute("producer", "fe_server");
  writer_.set_attribute("deck", model.source);
  writer_.set_attribute("title", model.title);
  for (const auto& [name, value] : model.run_attributes) writer_.set_attribute(name, value);
  const double global = model.history_dt_global > 0.0 ? model.history_dt_global : default_interval;
  every_[0] = steps_per_row(global, fe_dt);
  every_[1] = steps_per_row(model.history_dt_nodes > 0.0 ? model.history_dt_nodes : global, fe_dt);
  every_[2] = steps_per_row(model.history_dt_elements > 0.0 ? model.history_dt_elements : global, fe_dt);
  writer_.add_series("time", "s");
  if (table) {
    writer_.set_attribute("port_table", table->source);
    for (const auto& v : table->to_fe) writer_.add_series("ports/" + v.name(), config::unit(v.quantity));
    for (const auto& v : table->to_host) writer_.add_series("ports/" + v.name(), config::unit(v.quantity));
  }
  if (!model.contacts.empty()) {
    writer_.add_series("contact/force", "N");
    writer_.add_series("contact/max_penetration", "m");
  }
  for (const char* e : {"kinetic", "internal", "hourglass", "contact", "damping", "external_work", "balance_error"})
    writer_.add_series(std::string("energy/") + e, "J");
  // Each part's hourglass energy (parts in id order; 0 for a part without
  // deformable solids): where the zero-energy modes take energy. A group of
  // its own: readers take every member of energy/ for a series.
  if (!model.solids.empty() || !model.axis.empty())
    for (const auto& [pid, part] : model.parts) writer_.add_series("part_energy/hourglass/" + std::to_string(pid), "J");
  if (!model.history_nodes.empty()) {
    stream_[1] = writer_.add_stream();
    writer_.add_series("time_nodes", "s", stream_[1]);
  }
  for (int i : model.history_nodes) {
    std::string base = "nodes/" + std::to_string(model.node_ids[static_cast<size_t>(i)]) + "/";
    for (const char* c : {"ux", "uy", "uz"}) writer_.add_series(base + c, "m", stream_[1]);
    for (const char* c : {"vx", "vy", "vz"}) writer_.add_series(base + c, "m/s", stream_[1]);
  }
  if (!model.history_solids.empty() || !model.history_axis.empty() || !model.history_bars.empty() ||
      !model.cross_sections.empty()) {
    stream_[2] = writer_.add_stream();
    writer_.add_series("time_elements", "s", stream_[2]);
  }
  for (int e : model.history_solids) {
    std::string base = "solids/" + std::to_string(model.solids[static_cast<size_t>(e)].id) + "/";
    for (const char* c : {"sxx", "syy", "szz", "sxy", "syz", "szx"}) writer_.add_series(base + c, "Pa", stream_[2]);
    solid_plastic_.push_back(plastic_part(model, model.solids[static_cast<size_t>(e)].part));
    if (solid_plastic_.back()) writer_.add_series(base + "plastic_strain", "1", stream_[2]);
  }
  for (int e : model.history_axis) {
    // Axisymmetric: x is the radius, y the axis; von Mises for a quick look.
    std::string base = "axisymmetric/" + std::to_string(model.axis[static_cast<size_t>(e)].id) + "/";
    for (const char* c : {"radial", "axial", "hoop", "shear_ry", "von_mises"})
      writer_.add_series(base + c, "Pa", stream_[2]);
    axis_plastic_.push_back(plastic_part(model, model.axis[static_cast<size_t>(e)].part));
    if (axis_plastic_.back()) writer_.add_series(base + "plastic_strain", "1", stream_[2]);
  }
  for (int e : model.history_bars) {
    // The bar's stress and its particle velocity along the axis (n1 → n2):
    // together they separate the waves running each way (σ = ∓ρc·v).
    const std::string base = "bars/" + std::to_string(model.bars[static_cast<size_t>(e)].id) + "/";
    writer_.add_series(base + "axial_stress", "Pa", stream_[2]);
    writer_.add_series(base + "axial_velocity", "m/s", stream_[2]);
  }
  for (const CrossSection& cs : model.cross_sections) {
    // Beyond LS-DYNA's SECFORC: the cut's mean velocity (its nodes weighted
    // by mass: the cut's momentum over its mass). With the force it separates
    // the waves running each way through the cut (σ = ∓ρc·v). In a 2D
    // axisymmetric deck only the axial components exist: a full ring's
    // radial forces and velocities cancel around it.
    for (int c : section_components_) {
      writer_.add_series("sections/" + std::to_string(cs.id) + "/f" + "xyz"[c], "N", stream_[2]);
      writer_.add_series("sections/" + std::to_string(cs.id) + "/v" + "xyz"[c], "m/s", stream_[2]);
    }
    double total = 0.0;
    for (int n : cs.nodes) total += model.mass[static_cast<size_t>(n)];
    std::vector<double> w;
    for (int n : cs.nodes) w.push_back(total > 0.0 ? model.mass[static_cast<size_t>(n)] / total : 1.0 / cs.nodes.size());
    section_weights_.push_back(std::move(w));
  }
  size_t widest = 0;
  for (size_t k : {stream_[0], stream_[1], stream_[2]}) widest = std::max(widest, writer_.columns(k));
  row_.resize(widest);
  if (!model.ascii_dt.empty())
    ascii_ = std::make_unique<AsciiOutput>(std::filesystem::path(path).parent_path().string(), model, fe_dt, resume);
  if (model.snapshot_interval > 0.0) {
    std::string base = path.size() > 3 && path.compare(path.size() - 3, 3, ".h5") == 0 ? path.substr(0, path.size() - 3) : path;
    fields_ = std::make_unique<FieldWriter>(base + "_fields.h5", model, resume);  // writes the snapshot at t = 0 unless resuming
    next_snapshot_ = model.snapshot_interval;
  }
  if (!model.fatigue.empty()) fatigue_ = std::make_unique<FatigueTracker>(model, fe_dt);
  // A new file opens from now on, whatever kills the process (a resumed
  // one once state() has cut it back to the checkpoint's rows).
  if (!resume) writer_.start_writing();
}

History::~History() = default;

FollowerHistory::FollowerHistory(const Model& model, double fe_dt)
    : model_(model), fe_dt_(fe_dt), next_snapshot_(model.snapshot_interval) {}

void FollowerHistory::record(const Solver& s) {
  // History::record's order: the ASCII files first, then the snapshot.
  for (int k = AsciiOutput::velocity_reads(model_, fe_dt_, s.step_count()); k > 0; --k) {
    std::vector<Vec3> v;
    s.gather_velocities(v);
  }
  // The same test as History::record's, on the same (shared) time.
  if (model_.snapshot_interval > 0.0 && s.time() >= next_snapshot_ - 1e-12 * model_.snapshot_interval) {
    std::vector<Vec3> x, v;
    std::vector<Eigen::Matrix<double, 6, 1>> stress;
    std::vector<double> plastic;
    s.gather_fields(x, v, stress, plastic, model_.solids.empty() && !model_.axis.empty());
    next_snapshot_ += model_.snapshot_interval;
  }
}

void History::flush() {
  writer_.flush();
  if (ascii_) ascii_->flush();
}

void History::state(config::StateIO& io) {
  io.value("history energy scale", energy_scale_);
  io.value("history next snapshot", next_snapshot_);
  uint64_t has_fields = fields_ != nullptr;
  io.expect("history fields", has_fields, "field snapshots (*DATABASE_BINARY_D3PLOT)");
  if (fields_) fields_->state(io);
  uint64_t has_ascii = ascii_ != nullptr;
  io.expect("history ascii", has_ascii, "LS-DYNA ASCII files");
  if (ascii_) ascii_->state(io);
  uint64_t has_fatigue = fatigue_ != nullptr;
  io.expect("history fatigue", has_fatigue, "fatigue counting (*PCS_FATIGUE_PART)");
  if (fatigue_) fatigue_->state(io);
  for (size_t k = 0; k < 3; ++k) {
    if (k > 0 && stream_[k] == 0) continue;  // a stream this model does not write
    uint64_t rows = writer_.rows(stream_[k]);
    io.value("history rows", rows);
    if (!io.saving()) writer_.resume_at(static_cast<size_t>(rows), stream_[k]);
  }
  if (!io.saving()) writer_.start_writing();
}

std::string History::fatigue_report(double time) const { return fatigue_ ? fatigue_->report(time) : std::string(); }

void History::write_fatigue_table(const std::string& path, double time) const {
  if (fatigue_) fatigue_->write_csv(path, time);
}

size_t History::snapshots() const { return fields_ ? fields_->snapshots() : 0; }

std::string History::fields_path() const { return fields_ ? fields_->xdmf_path() : std::string(); }

std::string History::energy_summary(const Solver& s, bool* exceeded, bool* failed) const {
  const double err = s.energies().balance_error;
  const double scale = std::max(energy_scale_, 1e-300);
  char buf[200];
  std::snprintf(buf, sizeof buf, "energy balance error %.4g J (%.3g %% of %.4g J, bound 1 %%)", err,
                100.0 * std::fabs(err) / scale, energy_scale_);
  judge_energy(err, energy_scale_, exceeded, failed);
  return buf;
}

void History::judge_energy(double error, double scale, bool* exceeded, bool* failed) {
  const bool held = scale > 0.0;  // a run that held no energy has nothing to judge
  if (exceeded) *exceeded = held && std::fabs(error) > 0.01 * scale;
  if (failed) *failed = held && (std::fabs(error) > kEnergyFailFactor * 0.01 * scale || !std::isfinite(error));
}

bool History::plastic_part(const Model& m, int part) { return m.materials.at(m.parts.at(part).material).plastic; }

void History::record(const Solver& s, const std::vector<double>& inputs,
                     const std::vector<double>& outputs) {
  const Energies& e = s.energies();
  // The scale of the balance: the most energy the model held (springs included) or was given, every step.
  energy_scale_ = std::max({energy_scale_, e.kinetic + e.internal + e.spring, std::fabs(e.external_work)});
  const long n = s.step_count();
  if (n % every_[0] == 0) {
    size_t k = 0;
    row_[k++] = s.time();
    for (double v : inputs) row_[k++] = v;
    for (double v : outputs) row_[k++] = v;
    if (!model_.contacts.empty()) {
      row_[k++] = s.contact_force();
      row_[k++] = s.max_penetration();
    }
    for (double v : {e.kinetic, e.internal, e.hourglass, e.contact, e.damping, e.external_work, e.balance_error})
      row_[k++] = v;
    if (!model_.solids.empty() || !model_.axis.empty())
      for (size_t j = 0; j < model_.parts.size(); ++j) row_[k++] = j < e.part_hourglass.size() ? e.part_hourglass[j] : 0.0;
    writer_.append(row_, stream_[0]);
  }
  if (!model_.history_nodes.empty() && n % every_[1] == 0) {
    size_t k = 0;
    row_[k++] = s.time();
    for (int i : model_.history_nodes) {
      const size_t node = static_cast<size_t>(i);
      for (int c = 0; c < 3; ++c) row_[k++] = s.x_live()[node][c] - model_.x0[node][c];
      for (int c = 0; c < 3; ++c) row_[k++] = s.v_live()[node][c];
    }
    writer_.append(row_, stream_[1]);
  }
  if (stream_[2] != 0 && n % every_[2] == 0) {
    // Stresses and section forces are those of x_n, the state at the step's
    // start: the row carries that time, and the velocities of that time.
    size_t k = 0;
    row_[k++] = s.stress_time();
    for (size_t h = 0; h < model_.history_solids.size(); ++h) {
      const size_t el = static_cast<size_t>(model_.history_solids[h]);
      for (int c = 0; c < 6; ++c) row_[k++] = s.stress(el)(c);
      if (solid_plastic_[h]) row_[k++] = s.plastic_strain(el);
    }
    for (size_t h = 0; h < model_.history_axis.size(); ++h) {
      const size_t el = static_cast<size_t>(model_.history_axis[h]);
      const auto& sg = s.axi_stress(el);
      for (int c = 0; c < 4; ++c) row_[k++] = sg(c);
      row_[k++] = von_mises(sg);
      if (axis_plastic_[h]) row_[k++] = s.axi_plastic_strain(el);
    }
    for (int el : model_.history_bars) {
      row_[k++] = s.bar_stress(static_cast<size_t>(el));
      row_[k++] = s.bar_axial_velocity(static_cast<size_t>(el));
    }
    for (size_t cs = 0; cs < model_.cross_sections.size(); ++cs) {
      const Vec3 f = s.section_force(cs);
      Vec3 v = Vec3::Zero();
      const auto& nodes = model_.cross_sections[cs].nodes;
      for (size_t i = 0; i < nodes.size(); ++i) v += section_weights_[cs][i] * s.velocity_at_stress_time(static_cast<size_t>(nodes[i]));
      for (int c : section_components_) row_[k++] = f[c], row_[k++] = v[c];
    }
    writer_.append(row_, stream_[2]);
  }
  if (fatigue_) fatigue_->sample(s);  // every FE step: the stress's turning points, not a decimated history's
  if (ascii_) ascii_->record(s);
  if (fields_ && s.time() >= next_snapshot_ - 1e-12 * model_.snapshot_interval) {
    fields_->write(s, fatigue_ ? fatigue_->damage_field() : std::vector<double>{});
    next_snapshot_ += model_.snapshot_interval;
  }
}

}  // namespace fe
