// Squeeze-film damping between two parallel faces that approach each other
// along the axis, e.g. a valve spool's end face and its stop: the oil has to
// leave the narrowing gap radially, and the pressure that takes pushes the
// faces apart. For an annulus (radii r_i < r_o, the film open to the same
// pressure at both rims, incompressible and isoviscous) Reynolds' equation
// gives the classic result
//
//   F = (3·π·μ / (2·h³)) · G · (−ḣ),   G = r_o⁴ − r_i⁴ − (r_o² − r_i²)² / ln(r_o/r_i)
//
// (G = r_o⁴ for a full disc; e.g. Hamrock, Schmid & Jacobson, "Fundamentals
// of Fluid Film Lubrication", the parallel-surface squeeze film). The film
// only pushes: while the faces separate its pressure would fall below the
// surrounding oil's, it cavitates, and the chamber's own pressure (a
// co-simulation port) is all that acts (the half-Sommerfeld condition).
// Below h_min (the faces' roughness) the coefficient is held at its h_min
// value, and at h ≤ 0 the faces touch: the film has broken down and the
// stop's own contact (the host's stop spring, a contact) carries alone.
//
// The coefficient grows as 1/h³, far beyond what an explicit damper can
// carry at the FE step (a 0.2 kg spool 14 µm from its stop needs ~3e5 N·s/m),
// so the force is solved with the end-of-step velocity (UserLoad's stage 6):
// unconditionally stable. It acts between the two node sets along the
// axis, shared by nodal mass, on their mass-weighted mean motion.
#pragma once

#include <vector>

#include "loads/user_load.hpp"

namespace fe {

// The film's coefficient K = (3·π·μ/2)·G, N·s·m (force = K·|ḣ|/h³).
double squeeze_film_coefficient(double viscosity, double r_out, double r_in);

class SqueezeFilmLoad : public UserLoad {
 public:
  explicit SqueezeFilmLoad(const Model& model);  // an InputError names the card of a bad film
  bool empty() const { return films_.empty(); }
  // Stage 2: only records the gaps at x_n (the force is solved at stage 6).
  void apply(double t, const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& f_ext) override;
  bool loaded_nodes(std::vector<int>& nodes) const override;
  void apply_implicit(const Mobility& mob, const std::vector<Vec3>& v_old, const std::vector<Vec3>& v_pred,
                      std::vector<NodalForce>& out) override;
  // The gaps at x_n (stage 6 of the next step reads them).
  void state(config::StateIO& io) override;

 private:
  struct Side {
    std::vector<int> nodes;
    std::vector<double> weight;  // nodal mass / the side's mass
  };
  struct Film {
    Side one, two;
    double direction = 1.0, h0 = 0.0, u0 = 0.0, K = 0.0, h_min = 0.0;
    double h = 0.0;  // the gap at x_n (stage 2)
    double S = -1.0;  // the relative velocity's answer to a unit force pair per unit h (built on first use)
  };
  double mean_axial(const Side& s, const std::vector<Vec3>& field) const;
  double mobility(const Film& f, const Mobility& mob) const;
  const Model& model_;
  std::vector<Film> films_;
};

}  // namespace fe
