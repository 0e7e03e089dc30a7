#include "loads/squeeze_film.hpp"

#include <cmath>
#include <map>

#include "config/keyword_reader.hpp"

namespace fe {

double squeeze_film_coefficient(double viscosity, double r_out, double r_in) {
  const double ro2 = r_out * r_out, ri2 = r_in * r_in;
  double G = ro2 * ro2;
  if (r_in > 0.0) G = ro2 * ro2 - ri2 * ri2 - (ro2 - ri2) * (ro2 - ri2) / std::log(r_out / r_in);
  return 1.5 * M_PI * viscosity * G;
}

SqueezeFilmLoad::SqueezeFilmLoad(const Model& model) : model_(model) {
  for (const SqueezeFilmDef& d : model.squeeze_films) {
    Film f;
    auto side = [&](int set_id, const char* name) {
      const auto it = model.node_sets.find(set_id);
      if (it == model.node_sets.end())
        throw config::InputError(d.where, std::string(name) + " " + std::to_string(set_id) + " is not a *SET_NODE");
      Side s;
      double total = 0.0;
      for (int id : it->second) {
        s.nodes.push_back(model.index_of(id, d.where));
        total += model.mass[static_cast<size_t>(s.nodes.back())];
      }
      if (!(total > 0.0))
        throw config::InputError(d.where, std::string(name) + " " + std::to_string(set_id) + " has no mass (no element or mass on its nodes)");
      for (int n : s.nodes) s.weight.push_back(model.mass[static_cast<size_t>(n)] / total);
      return s;
    };
    f.one = side(d.set1, "NSID1");
    f.two = side(d.set2, "NSID2");
    f.direction = d.direction;
    f.h0 = d.h0;
    f.h = d.h0;
    f.K = squeeze_film_coefficient(d.viscosity, d.r_out, d.r_in);
    f.h_min = d.h_min;
    f.u0 = mean_axial(f.one, model.x0) - mean_axial(f.two, model.x0);
    films_.push_back(std::move(f));
  }
}

double SqueezeFilmLoad::mean_axial(const Side& s, const std::vector<Vec3>& field) const {
  const int a = model_.symmetry_axis;
  double sum = 0.0;
  for (size_t k = 0; k < s.nodes.size(); ++k) sum += s.weight[k] * field[static_cast<size_t>(s.nodes[k])][a];
  return sum;
}

bool SqueezeFilmLoad::loaded_nodes(std::vector<int>& nodes) const {
  for (const Film& f : films_) {
    nodes.insert(nodes.end(), f.one.nodes.begin(), f.one.nodes.end());
    nodes.insert(nodes.end(), f.two.nodes.begin(), f.two.nodes.end());
  }
  return true;
}

void SqueezeFilmLoad::apply(double, const std::vector<Vec3>& x, const std::vector<Vec3>&, std::vector<Vec3>&) {
  for (Film& f : films_) f.h = f.h0 + f.direction * (mean_axial(f.one, x) - mean_axial(f.two, x) - f.u0);
}

// How the mean relative velocity w = v̄1 − v̄2 answers a force F on side 1
// and −F on side 2 (each shared by the weights): Δw = h·S·F with
// S = Σ_G (1/m_G)·free_G·(W1_G − W2_G)², W_G a side's weight on group G.
double SqueezeFilmLoad::mobility(const Film& f, const Mobility& mob) const {
  std::map<int, double> W;  // group → W1 − W2
  for (size_t k = 0; k < f.one.nodes.size(); ++k) W[(*mob.group)[static_cast<size_t>(f.one.nodes[k])]] += f.one.weight[k];
  for (size_t k = 0; k < f.two.nodes.size(); ++k) W[(*mob.group)[static_cast<size_t>(f.two.nodes[k])]] -= f.two.weight[k];
  double S = 0.0;
  for (const auto& [g, w] : W) {
    const size_t G = static_cast<size_t>(g);
    S += (*mob.inv_mass)[G] * (*mob.free)[G][model_.symmetry_axis] * w * w;
  }
  return S;
}

void SqueezeFilmLoad::apply_implicit(const Mobility& mob, const std::vector<Vec3>& v_old,
                                     const std::vector<Vec3>& v_pred, std::vector<NodalForce>& out) {
  const int a = model_.symmetry_axis;
  const double th = mob.theta;
  for (Film& f : films_) {
    if (f.S < 0.0) f.S = mobility(f, mob);
    // The relative velocity at t_n without the film, and the gap's rate.
    const double w = (1.0 - th) * (mean_axial(f.one, v_old) - mean_axial(f.two, v_old)) +
                     th * (mean_axial(f.one, v_pred) - mean_axial(f.two, v_pred));
    if (f.direction * w >= 0.0) continue;  // opening: the film cavitates, no push
    if (f.h <= 0.0) continue;              // the faces touch: the stop's contact carries
    const double h = std::max(f.h, f.h_min);
    const double C = f.K / (h * h * h);
    // F = −C·w_n with w_n = w + θ·h_step·S·F. On the first step (θ = 0, v_0
    // known) the force is bounded the same way, so that it cannot reverse w.
    const double force = -C * w / (1.0 + (th > 0.0 ? th : 1.0) * mob.h * C * f.S);  // on side 1, along +axis
    for (size_t k = 0; k < f.one.nodes.size(); ++k) {
      NodalForce nf{f.one.nodes[k], Vec3::Zero()};
      nf.f[a] = force * f.one.weight[k];
      out.push_back(nf);
    }
    for (size_t k = 0; k < f.two.nodes.size(); ++k) {
      NodalForce nf{f.two.nodes[k], Vec3::Zero()};
      nf.f[a] = -force * f.two.weight[k];
      out.push_back(nf);
    }
  }
}

}  // namespace fe

namespace fe {

void SqueezeFilmLoad::state(config::StateIO& io) {
  io.expect("films", films_.size(), "the number of squeeze films");
  for (Film& f : films_) io.value("film gap", f.h);
}

}  // namespace fe
