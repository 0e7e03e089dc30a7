// J2 (von Mises) plasticity by radial return, for *MAT_PLASTIC_KINEMATIC
// (003, mixed hardening: BETA the isotropic share) and *MAT_PIECEWISE_
// LINEAR_PLASTICITY (024, isotropic, linear or a piecewise-linear yield
// curve). The return is exact for linear hardening and iterates over the
// curve's segments otherwise (Simo & Hughes, "Computational Inelasticity",
// 1998, the radial return of §3.3, with the mixed hardening of §3.3.2):
//
//   ξ = dev(σ_trial) − α,  q = √(3/2)·‖ξ‖,  f = q − σ_y(ε_p)
//   f > 0:  Δε_p solves q − (3G + (1 − β)·H)·Δε_p − σ_y(ε_p + Δε_p) = 0
//           Δγ = √(3/2)·Δε_p,  n = ξ/‖ξ‖
//           σ = σ_trial − 2G·Δγ·n,  α += (2/3)·(1 − β)·H·Δγ·n,  ε_p += Δε_p
//
// Tensors as Voigt arrays in the solids' order (xx, yy, zz, xy, yz, zx).
#pragma once

#include <cmath>

#include "model/model.hpp"

namespace fe {

// a += Δt·(W·a − a·W) for a symmetric tensor a and the spin W (w01 = W_xy,
// w12 = W_yz, w02 = W_xz): the Jaumann rate's rotation term.
__attribute__((always_inline)) inline void jaumann_rotate(double a[6], double w01, double w12, double w02, double dt) {
  const double s00 = a[0], s11 = a[1], s22 = a[2], s01 = a[3], s12 = a[4], s02 = a[5];
  a[0] += dt * 2.0 * (w01 * s01 + w02 * s02);
  a[1] += dt * 2.0 * (-w01 * s01 + w12 * s12);
  a[2] += dt * -2.0 * (w02 * s02 + w12 * s12);
  a[3] += dt * (w01 * s11 + w02 * s12 - w01 * s00 + w12 * s02);
  a[4] += dt * (-w01 * s02 + w12 * s22 - w02 * s01 - w12 * s11);
  a[5] += dt * (w01 * s12 + w02 * s22 - w02 * s00 - w12 * s01);
}

// Returns the trial stress sigma (in place) to the yield surface of `mat`
// with shear modulus G, updating the back stress alpha and the effective
// plastic strain ep. Returns the plastic strain increment (0: elastic).
inline double radial_return(const Material& mat, double G, double sigma[6], double alpha[6], double& ep) {
  const double p = (sigma[0] + sigma[1] + sigma[2]) / 3.0;
  double xi[6] = {sigma[0] - p - alpha[0], sigma[1] - p - alpha[1], sigma[2] - p - alpha[2],
                  sigma[3] - alpha[3],     sigma[4] - alpha[4],     sigma[5] - alpha[5]};
  const double norm = std::sqrt(xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2] +
                                2.0 * (xi[3] * xi[3] + xi[4] * xi[4] + xi[5] * xi[5]));
  const double q = std::sqrt(1.5) * norm;
  double slope = 0.0;
  const double sy = mat.yield_stress(ep, &slope);
  if (q <= sy) return 0.0;
  const double kinematic = (1.0 - mat.beta) * mat.plastic_modulus;
  double dep = (q - sy) / (3.0 * G + kinematic + slope);
  if (!mat.hardening_strain.empty())  // a piecewise-linear curve: Newton, exact once on the right segment
    for (int it = 0; it < 50; ++it) {
      const double g = q - (3.0 * G + kinematic) * dep - mat.yield_stress(ep + dep, &slope);
      if (std::fabs(g) <= 1e-12 * sy) break;
      dep += g / (3.0 * G + kinematic + slope);
    }
  const double dgamma = std::sqrt(1.5) * dep;
  const double k = 2.0 * G * dgamma / norm, ka = (2.0 / 3.0) * kinematic * dgamma / norm;
  for (int c = 0; c < 6; ++c) {
    sigma[c] -= k * xi[c];
    alpha[c] += ka * xi[c];
  }
  ep += dep;
  return dep;
}

// The plastic lanes of a batch of solids (element_hex8.hpp's SolidBatch:
// its plastic, two_mu, alpha and ep per lane): the back stress turns with
// the body too (the spin of the velocity gradient L), then the trial stress
// nsig returns to the yield surface, both in place.
template <class Batch, int W>
inline void plastic_lanes(Batch& B, const double (&L)[3][3][W], double (&nsig)[6][W], double dt) {
  for (int l = 0; l < W; ++l) {
    if (!B.plastic[l]) continue;
    const double w01 = 0.5 * (L[0][1][l] - L[1][0][l]), w12 = 0.5 * (L[1][2][l] - L[2][1][l]),
                 w02 = 0.5 * (L[0][2][l] - L[2][0][l]);
    double a[6], t[6];
    for (int c = 0; c < 6; ++c) a[c] = B.alpha[c][l], t[c] = nsig[c][l];
    jaumann_rotate(a, w01, w12, w02, dt);
    radial_return(*B.plastic[l], 0.5 * B.two_mu[l], t, a, B.ep[l]);
    for (int c = 0; c < 6; ++c) B.alpha[c][l] = a[c], nsig[c][l] = t[c];
  }
}

}  // namespace fe
