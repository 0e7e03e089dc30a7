#include "elements/element_tet4.hpp"

#include <algorithm>
#include <cmath>

#include "elements/element_plasticity.hpp"

namespace fe {

bool tet4_gradients(const Mat83& x, Eigen::Matrix<double, 4, 3>& b, double& volume) {
  const Eigen::Vector3d x1 = x.row(kTet4Corners[0]).transpose();
  const Eigen::Vector3d e1 = x.row(kTet4Corners[1]).transpose() - x1, e2 = x.row(kTet4Corners[2]).transpose() - x1,
                        e3 = x.row(kTet4Corners[3]).transpose() - x1;
  const Eigen::Vector3d c23 = e2.cross(e3), c31 = e3.cross(e1), c12 = e1.cross(e2);
  const double six_v = e1.dot(c23);
  volume = six_v / 6.0;
  if (!(six_v > 0.0)) return false;
  b.row(1) = c23.transpose() / six_v;
  b.row(2) = c31.transpose() / six_v;
  b.row(3) = c12.transpose() / six_v;
  b.row(0) = -(b.row(1) + b.row(2) + b.row(3));
  return true;
}

double tet4_characteristic_length(const Mat83& x) {
  Eigen::Matrix<double, 4, 3> b;
  double volume = 0.0;
  if (!tet4_gradients(x, b, volume)) return 0.0;
  return 1.0 / b.rowwise().norm().maxCoeff();  // |b_a| = 1/h_a
}

double tet4_stable_step(const Mat83& x, double lambda, double mu, double rho, double q2, double beta) {
  Eigen::Matrix<double, 4, 3> b;
  double volume = 0.0;
  if (!tet4_gradients(x, b, volume)) return 0.0;
  return stable_step_of_gradients<4>(b, lambda, mu, rho, q2, beta);
}

// Written lane by lane in arrays [..][W], every loop over lanes a vector
// operation, and cloned as the hexahedron's kernel is (element_hex8.cpp:
// the clones give the same bits).
template <bool Damped>
__attribute__((always_inline)) inline void tet4_kernel_impl(SolidBatch& B, double dt, double q1, double q2) {
  constexpr int W = SolidBatch::W;
  constexpr int c0 = kTet4Corners[0], c1 = kTet4Corners[1], c2 = kTet4Corners[2], c3 = kTet4Corners[3];
  // Gradients: b1..b3 from the edges' cross products over 6V, b0 = −Σ.
  double b[4][3][W], V[W], len[W];
  for (int l = 0; l < W; ++l) {
    double e[3][3];
    for (int i = 0; i < 3; ++i) {
      e[0][i] = B.x[c1][i][l] - B.x[c0][i][l];
      e[1][i] = B.x[c2][i][l] - B.x[c0][i][l];
      e[2][i] = B.x[c3][i][l] - B.x[c0][i][l];
    }
    const double g1[3] = {e[1][1] * e[2][2] - e[1][2] * e[2][1], e[1][2] * e[2][0] - e[1][0] * e[2][2],
                          e[1][0] * e[2][1] - e[1][1] * e[2][0]};
    const double g2[3] = {e[2][1] * e[0][2] - e[2][2] * e[0][1], e[2][2] * e[0][0] - e[2][0] * e[0][2],
                          e[2][0] * e[0][1] - e[2][1] * e[0][0]};
    const double g3[3] = {e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                          e[0][0] * e[1][1] - e[0][1] * e[1][0]};
    const double six_v = e[0][0] * g1[0] + e[0][1] * g1[1] + e[0][2] * g1[2];
    V[l] = six_v / 6.0;
    const double r = six_v > 0.0 ? 1.0 / six_v : 0.0;  // an inverted lane is reported by its volume
    double b2max = 0.0;
    for (int i = 0; i < 3; ++i) {
      b[1][i][l] = g1[i] * r, b[2][i][l] = g2[i] * r, b[3][i][l] = g3[i] * r;
      b[0][i][l] = -(b[1][i][l] + b[2][i][l] + b[3][i][l]);
    }
    for (int a = 0; a < 4; ++a) {
      const double n2 = b[a][0][l] * b[a][0][l] + b[a][1][l] * b[a][1][l] + b[a][2][l] * b[a][2][l];
      b2max = n2 > b2max ? n2 : b2max;
    }
    len[l] = b2max > 0.0 ? 1.0 / std::sqrt(b2max) : 0.0;  // the smallest altitude: |b_a| = 1/h_a
    B.volume[l] = V[l];
  }
  // Velocity gradient L_ij = Σ_a v_ai b_aj, exact.
  double L[3][3][W];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int l = 0; l < W; ++l)
        L[i][j][l] = B.v[c0][i][l] * b[0][j][l] + B.v[c1][i][l] * b[1][j][l] + B.v[c2][i][l] * b[2][j][l] +
                     B.v[c3][i][l] * b[3][j][l];
  // Trial stress σ + Δt·(C:D + W·σ − σ·W), the Jaumann rate.
  double nsig[6][W];
  for (int l = 0; l < W; ++l) {
    const double w01 = 0.5 * (L[0][1][l] - L[1][0][l]), w12 = 0.5 * (L[1][2][l] - L[2][1][l]),
                 w02 = 0.5 * (L[0][2][l] - L[2][0][l]);
    double t[6];
    for (int c = 0; c < 6; ++c) t[c] = B.sig[c][l];
    jaumann_rotate(t, w01, w12, w02, dt);
    const double trD = L[0][0][l] + L[1][1][l] + L[2][2][l], la = B.lambda[l] * trD, tm = B.two_mu[l];
    nsig[0][l] = t[0] + dt * (la + tm * L[0][0][l]);
    nsig[1][l] = t[1] + dt * (la + tm * L[1][1][l]);
    nsig[2][l] = t[2] + dt * (la + tm * L[2][2][l]);
    nsig[3][l] = t[3] + dt * tm * 0.5 * (L[0][1][l] + L[1][0][l]);
    nsig[4][l] = t[4] + dt * tm * 0.5 * (L[1][2][l] + L[2][1][l]);
    nsig[5][l] = t[5] + dt * tm * 0.5 * (L[2][0][l] + L[0][2][l]);
  }
  // Plastic lanes: the back stress turns with the body too, then the radial
  // return (element_plasticity.hpp).
  plastic_lanes(B, L, nsig, dt);
  // Bulk viscosity over the smallest altitude, energies; s = σ − q·I.
  double s[6][W];
  for (int l = 0; l < W; ++l) {
    const double d[6] = {L[0][0][l], L[1][1][l], L[2][2][l], 0.5 * (L[0][1][l] + L[1][0][l]),
                         0.5 * (L[1][2][l] + L[2][1][l]), 0.5 * (L[2][0][l] + L[0][2][l])};
    const double trD = d[0] + d[1] + d[2];
    B.limit[l] = B.spl[l] * len[l];
    const double q = trD < 0.0 ? B.rho[l] * len[l] * (q1 * len[l] * trD * trD - q2 * B.c[l] * trD) : 0.0;
    const double sd = 0.5 * ((B.sig[0][l] + nsig[0][l]) * d[0] + (B.sig[1][l] + nsig[1][l]) * d[1] +
                             (B.sig[2][l] + nsig[2][l]) * d[2]) +
                      (B.sig[3][l] + nsig[3][l]) * d[3] + (B.sig[4][l] + nsig[4][l]) * d[4] +
                      (B.sig[5][l] + nsig[5][l]) * d[5];
    B.internal[l] = V[l] * sd * dt;
    B.hourglass[l] = 0.0;
    B.damping_power[l] = -q * trD * V[l];
    for (int c = 0; c < 6; ++c) B.sig[c][l] = nsig[c][l], s[c][l] = c < 3 ? nsig[c][l] - q : nsig[c][l];
    if constexpr (Damped) {
      double g[6];
      B.damping_power[l] += stiffness_damping_stress(B.beta[l], B.lambda[l], B.two_mu[l], d, g) * V[l];
      for (int c = 0; c < 6; ++c) s[c][l] += g[c];
    }
  }
  // Forces f_a = −V·s·b_a at the corners (s in Voigt order xx yy zz xy yz
  // zx); the other slots are not written (the element loop adds none).
  for (int a = 0; a < 4; ++a)
    for (int l = 0; l < W; ++l) {
      const double bx = b[a][0][l], by = b[a][1][l], bz = b[a][2][l];
      B.f[kTet4Corners[a]][0][l] = -V[l] * (s[0][l] * bx + s[3][l] * by + s[5][l] * bz);
      B.f[kTet4Corners[a]][1][l] = -V[l] * (s[3][l] * bx + s[1][l] * by + s[4][l] * bz);
      B.f[kTet4Corners[a]][2][l] = -V[l] * (s[5][l] * bx + s[4][l] * by + s[2][l] * bz);
    }
}
__attribute__((target_clones("avx512f", "avx2", "default"))) void tet4_kernel_plain(SolidBatch& B, double dt, double q1,
                                                                                      double q2) {
  tet4_kernel_impl<false>(B, dt, q1, q2);
}
__attribute__((target_clones("avx512f", "avx2", "default"))) void tet4_kernel_damped(SolidBatch& B, double dt, double q1,
                                                                                       double q2) {
  tet4_kernel_impl<true>(B, dt, q1, q2);
}
void tet4_kernel(SolidBatch& B, double dt, double q1, double q2) {
  B.any_damped ? tet4_kernel_damped(B, dt, q1, q2) : tet4_kernel_plain(B, dt, q1, q2);
}

double solid_volume(const Mat83& x, const SolidElement& e) {
  double volume = 0.0;
  if (e.tet4) {
    Eigen::Matrix<double, 4, 3> b;
    tet4_gradients(x, b, volume);
  } else {
    Mat83 b;
    hex8_gradients(x, b, volume);
  }
  return volume;
}

double solid_mass_share(const SolidElement& e, int slot) {
  if (!e.tet4) return 1.0 / 8.0;
  return std::find(std::begin(kTet4Corners), std::end(kTet4Corners), slot) != std::end(kTet4Corners) ? 0.25 : 0.0;
}

double solid_stable_step(const Mat83& x, const SolidElement& e, double lambda, double mu, double rho, double q2,
                         double beta) {
  return e.tet4 ? tet4_stable_step(x, lambda, mu, rho, q2, beta) : hex8_stable_step(x, lambda, mu, rho, q2, beta);
}

double solid_characteristic_length(const Mat83& x, const SolidElement& e) {
  return e.tet4 ? tet4_characteristic_length(x) : hex8_characteristic_length(x, solid_volume(x, e));
}

}  // namespace fe
