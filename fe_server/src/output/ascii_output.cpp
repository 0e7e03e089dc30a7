#include "output/ascii_output.hpp"

#include <cmath>
#include <ctime>
#include <filesystem>
#include <map>
#include <stdexcept>

namespace fe {

namespace {
constexpr const char* kOrder[] = {"glstat", "matsum", "rcforc", "nodout", "elout"};
}

AsciiOutput::AsciiOutput(const std::string& dir, const Model& model, double fe_dt, bool resume)
    : m_(model), dt_(fe_dt), limit_(Solver::stable_dt(model)), last_wall_(std::chrono::steady_clock::now()) {
  for (const char* name : kOrder) {
    const auto it = model.ascii_dt.find(name);
    if (it == model.ascii_dt.end()) continue;
    File f;
    f.name = name;
    f.path = (std::filesystem::path(dir.empty() ? "." : dir) / name).string();
    f.every = std::max(1L, std::lround(it->second / fe_dt));
    if (!resume) {  // a restart opens its files once state() has cut them back
      f.out = std::fopen(f.path.c_str(), "w");
      if (!f.out) throw std::runtime_error("cannot write " + f.path);
      header(f.out);
      if (f.name == "matsum" || f.name == "nodout" || f.name == "elout" || f.name == "rcforc") std::fputs("\n", f.out);
    }
    files_.push_back(std::move(f));
  }
  // Each node's mass is shared by the parts of its elements, in proportion
  // to how many of its elements each part has.
  std::map<int, size_t> slot;
  for (const auto& [pid, part] : model.parts) {
    slot[pid] = part_ids_.size();
    part_ids_.push_back(pid);
  }
  std::vector<std::map<size_t, int>> count(model.x0.size());
  auto add = [&](int part, const int* nodes, int n) {
    for (int k = 0; k < n; ++k) ++count[static_cast<size_t>(nodes[k])][slot.at(part)];
  };
  for (const auto& e : model.solids) add(e.part, e.n, 8);
  for (const auto& e : model.axis) add(e.part, e.n, 4);
  for (const auto& e : model.bars) {
    const int n[2] = {e.n1, e.n2};
    add(e.part, n, 2);
  }
  part_nodes_.resize(part_ids_.size());
  part_share_.resize(part_ids_.size());
  for (size_t i = 0; i < count.size(); ++i) {
    int total = 0;
    for (const auto& [p, c] : count[i]) total += c;
    for (const auto& [p, c] : count[i]) {
      part_nodes_[p].push_back(static_cast<int>(i));
      part_share_[p].push_back(static_cast<double>(c) / total);
    }
  }
}

AsciiOutput::~AsciiOutput() {
  for (File& f : files_)
    if (f.out) std::fclose(f.out);
}

std::vector<std::string> AsciiOutput::files() const {
  std::vector<std::string> out;
  for (const File& f : files_) out.push_back(f.path);
  return out;
}

void AsciiOutput::header(std::FILE* f) const {
  char date[16];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%m/%d/%Y", std::localtime(&now));
  std::fprintf(f, " %.72s\n", m_.title.empty() ? m_.source.c_str() : m_.title.c_str());
  std::fprintf(f, "                         ls-dyna (version %-10s)     date %s\n", "fe_server", date);
}

int AsciiOutput::velocity_reads(const Model& model, double fe_dt, long n) {
  int reads = 0;
  for (const char* name : {"glstat", "matsum"}) {  // every = as the constructor computes it
    const auto it = model.ascii_dt.find(name);
    if (it != model.ascii_dt.end() && n % std::max(1L, std::lround(it->second / fe_dt)) == 0) ++reads;
  }
  return reads;
}

void AsciiOutput::record(const Solver& s) {
  const long n = s.step_count();
  for (File& f : files_) {
    if (!f.out || n % f.every != 0) continue;
    if (f.name == "glstat") glstat(f.out, s);
    else if (f.name == "matsum") matsum(f.out, s);
    else if (f.name == "rcforc") rcforc(f.out, s);
    else if (f.name == "nodout") nodout(f.out, s);
    else elout(f.out, s);
  }
}

void AsciiOutput::flush() {
  for (File& f : files_)
    if (f.out) std::fflush(f.out);
}

void AsciiOutput::state(config::StateIO& io) {
  io.expect("ascii files", files_.size(), "LS-DYNA ASCII files asked for (*DATABASE_GLSTAT, ...)");
  for (File& f : files_) {
    uint64_t bytes = f.out ? static_cast<uint64_t>(std::ftell(f.out)) : 0;
    io.value("ascii bytes", bytes);
    if (io.saving()) continue;
    // The blocks written after the checkpoint go; the file continues after it.
    std::error_code ec;
    std::filesystem::resize_file(f.path, bytes, ec);
    if (ec) throw config::CheckpointError("cannot continue " + f.path + ": " + ec.message());
    f.out = std::fopen(f.path.c_str(), "a");
    if (!f.out) throw config::CheckpointError("cannot continue " + f.path);
  }
}

void AsciiOutput::glstat(std::FILE* f, const Solver& s) {
  const Energies& e = s.energies();
  const long n = s.step_count();
  if (limit_.element_kind.empty())
    std::fprintf(f, "\n\n dt of cycle%8ld is controlled by load curve\n\n", n);
  else
    std::fprintf(f, "\n\n dt of cycle%8ld is controlled by %-11selement%8d\n\n", n, limit_.element_kind.c_str(),
                 limit_.element_id);
  const double total = e.kinetic + e.internal + e.spring + e.hourglass + e.damping + e.contact;
  // The initial total plus the work done since: total − balance error.
  const double reference = total - e.balance_error;
  Vec3 momentum = Vec3::Zero();
  double mass = 0.0;
  std::vector<Vec3> v;
  s.gather_velocities(v);  // every node's, at rank 0 across ranks
  for (size_t i = 0; i < v.size(); ++i) momentum += m_.mass[i] * v[i], mass += m_.mass[i];
  const Vec3 global = mass > 0.0 ? Vec3(momentum / mass) : Vec3::Zero();
  const auto now = std::chrono::steady_clock::now();
  const double cycles = static_cast<double>(n - last_step_) *
                        static_cast<double>(std::max<size_t>(1, m_.solids.size() + m_.axis.size() + m_.bars.size()));
  const long ns = cycles > 0.0 ? std::lround(std::chrono::duration<double, std::nano>(now - last_wall_).count() / cycles) : 0;
  last_wall_ = now;
  last_step_ = n;
  auto line = [&](const char* label, double value) { std::fprintf(f, " %s%14.5E\n", label, value); };
  line("time...........................", s.time());
  line("time step......................", s.dt());
  line("kinetic energy.................", e.kinetic);
  line("internal energy................", e.internal);
  line("spring and damper energy.......", e.spring);
  line("hourglass energy ..............", e.hourglass);
  line("system damping energy..........", e.damping);
  line("sliding interface energy.......", e.contact);
  line("external work..................", e.external_work);
  line("total energy...................", total);
  line("total energy / initial energy..", reference != 0.0 ? total / reference : 1.0);
  line("global x velocity..............", global.x());
  line("global y velocity..............", global.y());
  line("global z velocity..............", global.z());
  std::fprintf(f, " time per zone cycle.(nanosec)..%14ld\n", ns);
}

void AsciiOutput::matsum(std::FILE* f, const Solver& s) {
  const Energies& e = s.energies();
  std::vector<Vec3> v;
  s.gather_velocities(v);
  std::fprintf(f, "\n\n time =%13.4E\n", s.time());
  for (size_t p = 0; p < part_ids_.size(); ++p) {
    double ke = 0.0, mass = 0.0;
    Vec3 mom = Vec3::Zero();
    for (size_t k = 0; k < part_nodes_[p].size(); ++k) {
      const size_t i = static_cast<size_t>(part_nodes_[p][k]);
      const double mi = part_share_[p][k] * m_.mass[i];
      ke += 0.5 * mi * v[i].squaredNorm();
      mom += mi * v[i];
      mass += mi;
    }
    const Vec3 rbv = mass > 0.0 ? Vec3(mom / mass) : Vec3::Zero();
    const double ie = p < e.part_internal.size() ? e.part_internal[p] : 0.0;
    const double hg = p < e.part_hourglass.size() ? e.part_hourglass[p] : 0.0;
    if (part_ids_[p] < 100000)
      std::fprintf(f, " mat.#=%5d   ", part_ids_[p]);
    else
      std::fprintf(f, " mat.#=%8d", part_ids_[p]);
    std::fprintf(f, "          inten=%13.4E     kinen=%13.4E\n", ie, ke);
    std::fprintf(f, " x-mom=%13.4E     y-mom=%13.4E     z-mom=%13.4E\n", mom.x(), mom.y(), mom.z());
    std::fprintf(f, " x-rbv=%13.4E     y-rbv=%13.4E     z-rbv=%13.4E\n", rbv.x(), rbv.y(), rbv.z());
    std::fprintf(f, "                         hgeng=%13.4E     \n", hg);
  }
}

void AsciiOutput::rcforc(std::FILE* f, const Solver& s) {
  const auto& contacts = s.contacts();
  for (size_t k = 0; k < contacts.size(); ++k) {
    const PenaltyContact& c = *contacts[k];
    const Vec3& fs = c.slave_force();
    const Vec3& fm = c.master_force();
    std::fprintf(f, "  slave %11zu time%12.5E  x %12.5E  y %12.5E  z %12.5E mass %12.5E\n", k + 1, s.time(), fs.x(),
                 fs.y(), fs.z(), c.slave_mass());
    std::fprintf(f, "  master%11zu time%12.5E  x %12.5E  y %12.5E  z %12.5E mass %12.5E\n", k + 1, s.time(), fm.x(),
                 fm.y(), fm.z(), c.master_mass());
  }
}

void AsciiOutput::nodout(std::FILE* f, const Solver& s) {
  std::fprintf(f, "\n\n\n n o d a l   p r i n t   o u t   f o r   t i m e  s t e p%8ld                              ( at time%12.5E )\n",
               s.step_count(), s.time());
  std::fprintf(f, "\n nodal point  x-disp     y-disp      z-disp      x-vel       y-vel       z-vel      x-accl      "
                  "y-accl      z-accl      x-coor      y-coor      z-coor\n");
  const auto& x = s.x_live();
  const auto& v = s.v_live();
  const auto& v_old = s.v_previous();
  // v_{n+1/2} − v_{n−1/2} over the step's velocity update (the mean of two
  // unequal steps); the start step from the second step on, as before.
  const double h = s.step_count() <= 1 ? dt_ : s.velocity_step_taken();
  for (int node : m_.history_nodes) {
    const size_t i = static_cast<size_t>(node);
    const Vec3 u = x[i] - m_.x0[i];
    const Vec3 a = (v[i] - v_old[i]) / h;
    std::fprintf(f, "%9d%13.4E%12.4E%12.4E", m_.node_ids[i], u.x(), u.y(), u.z());
    std::fprintf(f, "%12.4E%12.4E%12.4E", v[i].x(), v[i].y(), v[i].z());
    std::fprintf(f, "%12.4E%12.4E%12.4E", a.x(), a.y(), a.z());
    std::fprintf(f, "%12.4E%12.4E%12.4E\n", x[i].x(), x[i].y(), x[i].z());
  }
}

void AsciiOutput::elout(std::FILE* f, const Solver& s) {
  // The stresses of the last step are those of its start, t_n (history.hpp).
  std::fprintf(f, "\n\n\n e l e m e n t   s t r e s s   c a l c u l a t i o n s   f o r   t i m e  s t e p%9ld   ( at time%12.5E )\n\n",
               s.step_count() - 1, s.stress_time());
  std::fprintf(f, " element  materl\n");
  std::fprintf(f, "     ipt  stress       sig-xx      sig-yy      sig-zz      sig-xy      sig-yz      sig-zx           "
                  "            yield\n           state                                                                  "
                  "              effsg      function\n");
  for (int el : m_.history_solids) {
    const size_t e = static_cast<size_t>(el);
    const SolidElement& se = m_.solids[e];
    const Material& mat = m_.materials.at(m_.parts.at(se.part).material);
    const double ep = s.plastic_strain(e);
    double slope = 0.0;
    const double yield = mat.plastic ? mat.yield_stress(ep, &slope) : 0.0;
    const auto& sig = s.stress(e);
    std::fprintf(f, "%8d-%7d\n", se.id, se.part);
    std::fprintf(f, "       1 %-7s ", ep > 0.0 ? "plastic" : "elastic");
    std::fprintf(f, "%12.4E%12.4E%12.4E", sig(0), sig(1), sig(2));
    std::fprintf(f, "%12.4E%12.4E%12.4E%14.4E%14.4E\n", sig(3), sig(4), sig(5), ep, yield);
  }
}

}  // namespace fe
