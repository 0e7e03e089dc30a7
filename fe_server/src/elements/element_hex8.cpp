#include "elements/element_hex8.hpp"
#include "elements/element_plasticity.hpp"
#include "elements/element_tet4.hpp"

#include <Eigen/Geometry>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <algorithm>
#include <functional>

#include "parallel/thread_pool.hpp"

namespace fe {

namespace {
// Natural coordinates of the 8 nodes (LS-DYNA order).
constexpr double kXi[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                              {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
// Hourglass base vectors: products of the natural coordinates, ξη, ηζ, ζξ, ξηζ.
const Eigen::Matrix<double, 4, 8> kH = [] {
  Eigen::Matrix<double, 4, 8> h;
  for (int a = 0; a < 8; ++a) {
    const double xi = kXi[a][0], eta = kXi[a][1], zeta = kXi[a][2];
    h(0, a) = xi * eta;
    h(1, a) = eta * zeta;
    h(2, a) = zeta * xi;
    h(3, a) = xi * eta * zeta;
  }
  return h;
}();
constexpr int kFaces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
}  // namespace

bool hex8_gradients(const Mat83& x, Mat83& b, double& volume) {
  // ∂N_a/∂ξ at the centre: ξ_a/8 (each shape function is (1 + ξ_a ξ)(1 + η_a η)(1 + ζ_a ζ)/8).
  Mat83 dN;
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i) dN(a, i) = kXi[a][i] / 8.0;
  const Eigen::Matrix3d J = x.transpose() * dN;  // J_ij = Σ_a x_ai ∂N_a/∂ξ_j
  const double det = J.determinant();
  volume = 8.0 * det;
  if (!(det > 0.0)) return false;
  b = dN * J.inverse();  // ∂N_a/∂x_k = Σ_j ∂N_a/∂ξ_j (J⁻¹)_jk
  return true;
}

Eigen::Matrix<double, 4, 8> hex8_hourglass_shapes(const Mat83& x, const Mat83& b) {
  // γ_α = h_α − (h_α·x_i) b_i
  const Eigen::Matrix<double, 4, 3> hx = kH * x;
  return kH - hx * b.transpose();
}

double hex8_characteristic_length(const Mat83& x, double volume) {
  double a_max = 0.0;
  for (const auto& f : kFaces) {
    const Eigen::Vector3d d1 = x.row(f[2]) - x.row(f[0]), d2 = x.row(f[3]) - x.row(f[1]);
    a_max = std::max(a_max, 0.5 * d1.cross(d2).norm());
  }
  return a_max > 0.0 ? volume / a_max : 0.0;
}

template <int N>
double stable_step_of_gradients(const Eigen::Matrix<double, N, 3>& b, double lambda, double mu, double rho, double q2,
                                double beta) {
  // B (6×3N, engineering shear) and the 6×6 product B·Bᵀ.
  Eigen::Matrix<double, 6, 3 * N> B = Eigen::Matrix<double, 6, 3 * N>::Zero();
  for (int a = 0; a < N; ++a) {
    const double bx = b(a, 0), by = b(a, 1), bz = b(a, 2);
    B(0, 3 * a) = bx, B(1, 3 * a + 1) = by, B(2, 3 * a + 2) = bz;
    B(3, 3 * a) = by, B(3, 3 * a + 1) = bx;
    B(4, 3 * a + 1) = bz, B(4, 3 * a + 2) = by;
    B(5, 3 * a) = bz, B(5, 3 * a + 2) = bx;
  }
  const Eigen::Matrix<double, 6, 6> G = B * B.transpose();
  Eigen::Matrix<double, 6, 6> D = Eigen::Matrix<double, 6, 6>::Zero();
  D.topLeftCorner<3, 3>().setConstant(lambda);
  for (int i = 0; i < 3; ++i) D(i, i) = lambda + 2.0 * mu, D(i + 3, i + 3) = mu;
  // λ_max(D·G) = λ_max(Lᵀ·G·L) with D = L·Lᵀ, a symmetric problem.
  const Eigen::Matrix<double, 6, 6> L = D.llt().matrixL();
  const Eigen::Matrix<double, 6, 6> S = L.transpose() * G * L;
  const double lmax = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(S, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
  const double omega = std::sqrt(N * lmax / rho);
  return damped_stable_step(omega, q2, beta);
}
template double stable_step_of_gradients<4>(const Eigen::Matrix<double, 4, 3>&, double, double, double, double, double);
template double stable_step_of_gradients<8>(const Eigen::Matrix<double, 8, 3>&, double, double, double, double, double);

double hex8_stable_step(const Mat83& x, double lambda, double mu, double rho, double q2, double beta) {
  Mat83 b;
  double volume = 0.0;
  if (!hex8_gradients(x, b, volume)) return 0.0;
  return stable_step_of_gradients<8>(b, lambda, mu, rho, q2, beta);
}

Mat83 hex8_gather(const std::vector<Vec3>& a, const SolidElement& e) {
  Mat83 out;
  for (int k = 0; k < 8; ++k) out.row(k) = a[static_cast<size_t>(e.n[k])].transpose();
  return out;
}

size_t hex8_block_size(size_t elements) {
  const size_t eighth = (elements / 8 + kHex8Lanes - 1) / kHex8Lanes * kHex8Lanes;
  return std::clamp<size_t>(eighth, 256, 2048);
}

Hex8State::Hex8State(const Model& m, const std::vector<int>* owner, int rank)
    : sigma(m.solids.size(), Eigen::Matrix<double, 6, 1>::Zero()),
      plastic_strain(m.solids.size(), 0.0),
      back_stress(m.solids.size(), Eigen::Matrix<double, 6, 1>::Zero()) {
  // The deformable elements this rank computes: the hexahedra first, then
  // the tetrahedra, so that a batch is of one kind.
  for (const bool tets : {false, true}) {
    if (tets) first_tet = elements.size();
    for (size_t e = 0; e < m.solids.size(); ++e) {
      const SolidElement& el = m.solids[e];
      if (el.tet4 == tets && !m.materials.at(m.parts.at(el.part).material).rigid && (!owner || (*owner)[e] == rank))
        elements.push_back(static_cast<int>(e));
    }
  }
  for (const int index : elements) {
    const SolidElement& el = m.solids[static_cast<size_t>(index)];
    const Part& part = m.parts.at(el.part);
    const Material& mat = m.materials.at(part.material);
    const Mat83 x0 = hex8_gather(m.x0, el);
    const double volume = solid_volume(x0, el);
    hourglass.push_back(el.tet4 ? 0.0 : m.hourglass_q * mat.rho * mat.wave_speed() * std::cbrt(volume * volume) / 4.0);
    // The element's own stable step (mass scaling included) per unit of its
    // characteristic length (V/A_max; a tetrahedron's smallest altitude):
    // the step it allows later is this times its length then (the wave
    // speed taken as constant).
    const double len0 = solid_characteristic_length(x0, el);
    const double step0 =
        solid_stable_step(x0, el, mat.lambda(), mat.mu(), mat.rho * el.mass_scale, m.bulk_q2, part.stiffness_damping);
    step_per_length.push_back(len0 > 0.0 && step0 > 0.0 ? step0 / len0 : 1e300);
    const int slot = fe::part_slot(m, el.part);
    part_slot.push_back(slot);
    std::array<int, 8> n;
    std::copy(el.n, el.n + 8, n.begin());
    nodes.push_back(n);
    if (parts.size() <= static_cast<size_t>(slot)) parts.resize(static_cast<size_t>(slot) + 1);
    parts[static_cast<size_t>(slot)] = {mat.lambda(), 2.0 * mat.mu(), mat.rho, mat.wave_speed(), part.stiffness_damping,
                                        mat.plastic ? &mat : nullptr};
  }
  force.assign(24 * elements.size(), 0.0);
  block = hex8_block_size(elements.size());
  blocks.resize((elements.size() + block - 1) / block);
  for (BlockResult& b : blocks) b.part_internal.assign(m.parts.size(), 0.0), b.part_hourglass.assign(m.parts.size(), 0.0);
  const std::vector<char> kept = corner_force_nodes(m);
  gather.build(m.x0.size(), elements.size(), 8, 3, block, [&](size_t k, int a) { return nodes[k][static_cast<size_t>(a)]; },
               [&](int i) { return kept[static_cast<size_t>(i)] != 0; });
}

namespace {

constexpr int W = static_cast<int>(kHex8Lanes);

using Hex8Batch = SolidBatch;

// Sums of eight corner values u_a against the eight products of the
// corners' natural coordinates, all at once (a Walsh–Hadamard transform,
// 24 additions where the eight sums one by one take 56):
//   s[0] = Σ u_a,  s[1..3] = Σ ξ_a u_a, Σ η_a u_a, Σ ζ_a u_a,
//   s[4..7] = Σ ξη u_a, Σ ηζ u_a, Σ ζξ u_a, Σ ξηζ u_a  (the hourglass base
//   vectors h_α of the header, in its order).
// LS-DYNA's corners pair along ξ as (0,1), (3,2), (4,5), (7,6).
__attribute__((always_inline)) inline void corner_sums(const double (&u)[8][3][W], int i, int l, double s[8]) {
  // ξ: each pair's sum and its ξ-weighted difference, at (η, ζ) = (−,−), (+,−), (−,+), (+,+).
  const double p0 = u[1][i][l] + u[0][i][l], m0 = u[1][i][l] - u[0][i][l];
  const double p1 = u[2][i][l] + u[3][i][l], m1 = u[2][i][l] - u[3][i][l];
  const double p2 = u[5][i][l] + u[4][i][l], m2 = u[5][i][l] - u[4][i][l];
  const double p3 = u[6][i][l] + u[7][i][l], m3 = u[6][i][l] - u[7][i][l];
  // η, then ζ.
  const double pp0 = p1 + p0, pm0 = p1 - p0, pp1 = p3 + p2, pm1 = p3 - p2;
  const double mp0 = m1 + m0, mm0 = m1 - m0, mp1 = m3 + m2, mm1 = m3 - m2;
  s[0] = pp1 + pp0;
  s[1] = mp1 + mp0;
  s[2] = pm1 + pm0;
  s[3] = pp1 - pp0;
  s[4] = mm1 + mm0;
  s[5] = pm1 - pm0;
  s[6] = mp1 - mp0;
  s[7] = mm1 - mm0;
}

// The inverse: f_a = Σ_k c[k]·(the k-th product at corner a), for c[0] = 0
// (nodal forces have no constant part), into f[a][i][l].
__attribute__((always_inline)) inline void corner_values(const double c[8], int i, int l, double (&f)[8][3][W]) {
  // ζ: the coefficients of 1, ξ, η, ξη on each face ζ = ∓1.
  const double a0m = -c[3], a0p = c[3];
  const double axm = c[1] - c[6], axp = c[1] + c[6];
  const double aym = c[2] - c[5], ayp = c[2] + c[5];
  const double axym = c[4] - c[7], axyp = c[4] + c[7];
  // η: the coefficients of 1 and ξ on each edge (η, ζ).
  const double b0mm = a0m - aym, b0pm = a0m + aym, b0mp = a0p - ayp, b0pp = a0p + ayp;
  const double bxmm = axm - axym, bxpm = axm + axym, bxmp = axp - axyp, bxpp = axp + axyp;
  // ξ: the corners.
  f[0][i][l] = b0mm - bxmm, f[1][i][l] = b0mm + bxmm;
  f[3][i][l] = b0pm - bxpm, f[2][i][l] = b0pm + bxpm;
  f[4][i][l] = b0mp - bxmp, f[5][i][l] = b0mp + bxmp;
  f[7][i][l] = b0pp - bxpp, f[6][i][l] = b0pp + bxpp;
}

// The kernel (see the header for the formulation), written in the basis of
// the corner products above: with g_a = (ξ_a, η_a, ζ_a)/8 the shape
// functions' gradients at the centre in natural coordinates,
//   J_ij = Σ_a x_ai g_aj,  b_a = J⁻ᵀ g_a,  L_ij = Σ_a v_ai b_aj = Σ_k V̂_ik (J⁻¹)_kj
// with V̂_ik = Σ_a v_ai g_ak, and every nodal force f_a = Σ_k g_ak C_k + Σ_α h_αa D_α
// is one inverse transform: b_a is never formed. Cloned for AVX-512, AVX2
// and a baseline; the machine picks one at load time, the same for every
// thread (no FMA, -ffp-contract=off in CMakeLists.txt: the clones give the
// same bits). AVX-512 measured 2–3 % faster than AVX2 here (AMD EPYC).
template <bool Damped>
__attribute__((always_inline)) inline void hex8_kernel_impl(Hex8Batch& B, double dt, double q1, double q2) {
  constexpr int faces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  // Corner sums of x and v: Sx[k][i] = Σ_a x_ai·(product k at a).
  double Sx[8][3][W], Sv[8][3][W];
  for (int i = 0; i < 3; ++i)
    for (int l = 0; l < W; ++l) {
      double sx[8], sv[8];
      corner_sums(B.x, i, l, sx);
      corner_sums(B.v, i, l, sv);
      for (int k = 0; k < 8; ++k) Sx[k][i][l] = sx[k], Sv[k][i][l] = sv[k];
    }
  // Jacobian J_ij = Sx[1+j][i]/8, its determinant and inverse.
  double inv[3][3][W];
  for (int l = 0; l < W; ++l) {
    double J[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) J[i][j] = 0.125 * Sx[1 + j][i][l];
    const double c00 = J[1][1] * J[2][2] - J[1][2] * J[2][1];
    const double c01 = J[1][2] * J[2][0] - J[1][0] * J[2][2];
    const double c02 = J[1][0] * J[2][1] - J[1][1] * J[2][0];
    const double det = J[0][0] * c00 + J[0][1] * c01 + J[0][2] * c02;
    B.volume[l] = 8.0 * det;
    const double r = det > 0.0 ? 1.0 / det : 0.0;  // an inverted lane is reported by its volume
    inv[0][0][l] = c00 * r;
    inv[1][0][l] = c01 * r;
    inv[2][0][l] = c02 * r;
    inv[0][1][l] = (J[0][2] * J[2][1] - J[0][1] * J[2][2]) * r;
    inv[1][1][l] = (J[0][0] * J[2][2] - J[0][2] * J[2][0]) * r;
    inv[2][1][l] = (J[0][1] * J[2][0] - J[0][0] * J[2][1]) * r;
    inv[0][2][l] = (J[0][1] * J[1][2] - J[0][2] * J[1][1]) * r;
    inv[1][2][l] = (J[0][2] * J[1][0] - J[0][0] * J[1][2]) * r;
    inv[2][2][l] = (J[0][0] * J[1][1] - J[0][1] * J[1][0]) * r;
  }
  // Velocity gradient L_ij = Σ_k V̂_ik (J⁻¹)_kj, V̂_ik = Sv[1+k][i]/8.
  double L[3][3][W];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int l = 0; l < W; ++l)
        L[i][j][l] = 0.125 * (Sv[1][i][l] * inv[0][j][l] + Sv[2][i][l] * inv[1][j][l] + Sv[3][i][l] * inv[2][j][l]);
  // Largest face area (the bulk viscosity's length V/A): one square root.
  double a2max[W];
  for (int l = 0; l < W; ++l) a2max[l] = 0.0;
  for (const auto& fc : faces)
    for (int l = 0; l < W; ++l) {
      double d1[3], d2[3];
      for (int i = 0; i < 3; ++i) {
        d1[i] = B.x[fc[2]][i][l] - B.x[fc[0]][i][l];
        d2[i] = B.x[fc[3]][i][l] - B.x[fc[1]][i][l];
      }
      const double cx = d1[1] * d2[2] - d1[2] * d2[1], cy = d1[2] * d2[0] - d1[0] * d2[2],
                   cz = d1[0] * d2[1] - d1[1] * d2[0];
      const double a2 = cx * cx + cy * cy + cz * cz;
      a2max[l] = a2 > a2max[l] ? a2 : a2max[l];
    }
  // Stress update: σ + Δt·(C:D + W·σ − σ·W), the Jaumann rate (objective:
  // a rigid rotation turns the stress with the body), W = ½(L − Lᵀ).
  double nsig[6][W];
  for (int l = 0; l < W; ++l) {
    const double d0 = L[0][0][l], d1 = L[1][1][l], d2 = L[2][2][l];
    const double d01 = 0.5 * (L[0][1][l] + L[1][0][l]), d12 = 0.5 * (L[1][2][l] + L[2][1][l]),
                 d20 = 0.5 * (L[2][0][l] + L[0][2][l]);
    const double w01 = 0.5 * (L[0][1][l] - L[1][0][l]), w12 = 0.5 * (L[1][2][l] - L[2][1][l]),
                 w02 = 0.5 * (L[0][2][l] - L[2][0][l]);
    double t[6] = {B.sig[0][l], B.sig[1][l], B.sig[2][l], B.sig[3][l], B.sig[4][l], B.sig[5][l]};
    jaumann_rotate(t, w01, w12, w02, dt);
    const double la = B.lambda[l] * (d0 + d1 + d2), tm = B.two_mu[l];
    nsig[0][l] = t[0] + dt * (la + tm * d0);
    nsig[1][l] = t[1] + dt * (la + tm * d1);
    nsig[2][l] = t[2] + dt * (la + tm * d2);
    nsig[3][l] = t[3] + dt * tm * d01;
    nsig[4][l] = t[4] + dt * tm * d12;
    nsig[5][l] = t[5] + dt * tm * d20;
  }
  // Plastic lanes: the back stress turns with the body too, then the
  // radial return (element_plasticity.hpp).
  plastic_lanes(B, L, nsig, dt);
  // Bulk viscosity, energies; s = σ − q·I, the stress the forces carry.
  double s[6][W];
  for (int l = 0; l < W; ++l) {
    const double d0 = L[0][0][l], d1 = L[1][1][l], d2 = L[2][2][l];
    const double d01 = 0.5 * (L[0][1][l] + L[1][0][l]), d12 = 0.5 * (L[1][2][l] + L[2][1][l]),
                 d20 = 0.5 * (L[2][0][l] + L[0][2][l]);
    const double trD = d0 + d1 + d2;
    const double n0 = nsig[0][l], n1 = nsig[1][l], n2 = nsig[2][l], n3 = nsig[3][l], n4 = nsig[4][l], n5 = nsig[5][l];
    const double sd = 0.5 * ((B.sig[0][l] + n0) * d0 + (B.sig[1][l] + n1) * d1 + (B.sig[2][l] + n2) * d2) +
                      (B.sig[3][l] + n3) * d01 + (B.sig[4][l] + n4) * d12 + (B.sig[5][l] + n5) * d20;
    const double V = B.volume[l];
    B.internal[l] = V * sd * dt;
    const double a_max = 0.5 * std::sqrt(a2max[l]);
    const double len = a_max > 0.0 ? V / a_max : 0.0;
    B.limit[l] = B.spl[l] * len;
    const double q = trD < 0.0 ? B.rho[l] * len * (q1 * len * trD * trD - q2 * B.c[l] * trD) : 0.0;
    B.damping_power[l] = -q * trD * V;
    B.sig[0][l] = n0, B.sig[1][l] = n1, B.sig[2][l] = n2, B.sig[3][l] = n3, B.sig[4][l] = n4, B.sig[5][l] = n5;
    s[0][l] = n0 - q, s[1][l] = n1 - q, s[2][l] = n2 - q, s[3][l] = n3, s[4][l] = n4, s[5][l] = n5;
    if constexpr (Damped) {
      const double d[6] = {d0, d1, d2, d01, d12, d20};
      double g[6];
      B.damping_power[l] += stiffness_damping_stress(B.beta[l], B.lambda[l], B.two_mu[l], d, g) * V;
      for (int c = 0; c < 6; ++c) s[c][l] += g[c];
    }
  }
  // Hourglass (viscous FB): q_αi = Σ_a v_ai γ_αa with γ_α = h_α − (h_α·x_j) b_j,
  // i.e. q_αi = (h_α·v_i) − Σ_j (h_α·x_j) L_ij; f_ai −= c_h Σ_α γ_αa q_αi, whose
  // b part is Σ_k g_ak R_ki with R = J⁻¹·P, P_ji = Σ_α (h_α·x_j) q_αi.
  double hg_energy[W], D[4][3][W], P[3][3][W];
  for (int l = 0; l < W; ++l) hg_energy[l] = 0.0;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      for (int l = 0; l < W; ++l) P[j][i][l] = 0.0;
  for (int al = 0; al < 4; ++al)
    for (int l = 0; l < W; ++l) {
      const double hx0 = Sx[4 + al][0][l], hx1 = Sx[4 + al][1][l], hx2 = Sx[4 + al][2][l];
      double qa[3];
      for (int i = 0; i < 3; ++i) qa[i] = Sv[4 + al][i][l] - (hx0 * L[i][0][l] + hx1 * L[i][1][l] + hx2 * L[i][2][l]);
      for (int i = 0; i < 3; ++i) {
        P[0][i][l] += hx0 * qa[i];
        P[1][i][l] += hx1 * qa[i];
        P[2][i][l] += hx2 * qa[i];
        D[al][i][l] = -B.ch[l] * qa[i];
      }
      hg_energy[l] += qa[0] * qa[0] + qa[1] * qa[1] + qa[2] * qa[2];
    }
  // Nodal forces: f_a = −V·s·b_a (b_a = J⁻ᵀ g_a) plus the hourglass force,
  // as coefficients of g_a (C_ik = (T_ik + c_h R_ki)/8, T = −V·s·J⁻ᵀ) and
  // of h_α (D_αi = −c_h q_αi), then one inverse transform per direction.
  for (int l = 0; l < W; ++l) {
    const double V = B.volume[l], ch = B.ch[l];
    const double S[3][3] = {{s[0][l], s[3][l], s[5][l]}, {s[3][l], s[1][l], s[4][l]}, {s[5][l], s[4][l], s[2][l]}};
    for (int i = 0; i < 3; ++i) {
      double c[8];
      c[0] = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double T = -V * (S[i][0] * inv[k][0][l] + S[i][1] * inv[k][1][l] + S[i][2] * inv[k][2][l]);
        const double R = inv[k][0][l] * P[0][i][l] + inv[k][1][l] * P[1][i][l] + inv[k][2][l] * P[2][i][l];
        c[1 + k] = 0.125 * (T + ch * R);
      }
      for (int al = 0; al < 4; ++al) c[4 + al] = D[al][i][l];
      corner_values(c, i, l, B.f);
    }
    B.hourglass[l] = ch * hg_energy[l] * dt;
  }
}

// Batches without a damped lane (Part::stiffness_damping) run the kernel
// without the damping stress, as it was before damping came in.
__attribute__((target_clones("avx512f", "avx2", "default"))) void hex8_kernel_plain(Hex8Batch& B, double dt, double q1,
                                                                                      double q2) {
  hex8_kernel_impl<false>(B, dt, q1, q2);
}
__attribute__((target_clones("avx512f", "avx2", "default"))) void hex8_kernel_damped(Hex8Batch& B, double dt, double q1,
                                                                                       double q2) {
  hex8_kernel_impl<true>(B, dt, q1, q2);
}
void hex8_kernel(Hex8Batch& B, double dt, double q1, double q2) {
  B.any_damped ? hex8_kernel_damped(B, dt, q1, q2) : hex8_kernel_plain(B, dt, q1, q2);
}

// The batch of n elements from k0 (all hexahedra, or all tetrahedra: Tets).
// The slots that carry nodes: a tetrahedron's four corners (its other slots
// repeat them, and their force slots stay 0), a hexahedron's eight.
template <bool Tets>
void solid_batch(const Model& m, Hex8State& st, const std::vector<Vec3>& x, const std::vector<Vec3>& v, double dt,
                 size_t k0, int n, Hex8Batch& B, std::vector<Vec3>& f, BlockResult& r) {
  constexpr int corners = Tets ? 4 : 8;
  auto slot = [](int j) { return Tets ? kTet4Corners[j] : j; };
  for (int l = 0; l < W; ++l) {
    if (l < n) {
      const size_t k = k0 + static_cast<size_t>(l);
      const size_t e = static_cast<size_t>(st.elements[k]);
      const std::array<int, 8>& nodes = st.nodes[k];
      for (int j = 0; j < corners; ++j) {
        const int a = slot(j);
        const Vec3& xa = x[static_cast<size_t>(nodes[static_cast<size_t>(a)])];
        const Vec3& va = v[static_cast<size_t>(nodes[static_cast<size_t>(a)])];
        for (int i = 0; i < 3; ++i) B.x[a][i][l] = xa[i], B.v[a][i][l] = va[i];
      }
      const Hex8State::PartConstants& pc = st.parts[static_cast<size_t>(st.part_slot[k])];
      B.lambda[l] = pc.lambda, B.two_mu[l] = pc.two_mu, B.rho[l] = pc.rho, B.c[l] = pc.wave_speed, B.beta[l] = pc.beta;
      B.ch[l] = st.hourglass[k];
      B.spl[l] = st.step_per_length[k];
      for (int c = 0; c < 6; ++c) B.sig[c][l] = st.sigma[e](c);
      B.plastic[l] = pc.plastic;
      if (B.plastic[l]) {
        B.ep[l] = st.plastic_strain[e];
        for (int c = 0; c < 6; ++c) B.alpha[c][l] = st.back_stress[e](c);
      }
    } else {  // an idle lane: a unit cube at rest
      for (int a = 0; a < 8; ++a)
        for (int i = 0; i < 3; ++i) B.x[a][i][l] = 0.5 * kXi[a][i], B.v[a][i][l] = 0.0;
      B.lambda[l] = B.two_mu[l] = B.rho[l] = B.c[l] = B.ch[l] = B.beta[l] = 0.0;
      B.spl[l] = 1e300;
      for (int c = 0; c < 6; ++c) B.sig[c][l] = 0.0;
      B.plastic[l] = nullptr;
    }
  }
  B.any_damped = std::any_of(B.beta, B.beta + W, [](double b) { return b != 0.0; });
  if constexpr (Tets)
    tet4_kernel(B, dt, m.bulk_q1, m.bulk_q2);
  else
    hex8_kernel(B, dt, m.bulk_q1, m.bulk_q2);
  note_step_limits(B.limit, W, n, k0, r);
  for (int l = 0; l < n; ++l) {
    const size_t k = k0 + static_cast<size_t>(l);
    if (!(B.volume[l] > 0.0) && r.inverted < 0) {
      r.inverted = static_cast<long>(k);
      r.measure = B.volume[l];
    }
    const size_t e = static_cast<size_t>(st.elements[k]);
    for (int c = 0; c < 6; ++c) st.sigma[e](c) = B.sig[c][l];
    if (B.plastic[l]) {
      st.plastic_strain[e] = B.ep[l];
      for (int c = 0; c < 6; ++c) st.back_stress[e](c) = B.alpha[c][l];
    }
    const unsigned direct = st.gather.direct_corners(k);
    for (int j = 0; j < corners; ++j) {
      const int a = slot(j);
      if (direct & (1u << a)) {  // this block's own node: added here, in element order
        Vec3& fn = f[static_cast<size_t>(st.nodes[k][static_cast<size_t>(a)])];
        for (int i = 0; i < 3; ++i) fn[i] += B.f[a][i][l];
      } else {
        double* out = &st.force[24 * k + 3 * static_cast<size_t>(a)];
        for (int i = 0; i < 3; ++i) out[i] = B.f[a][i][l];
      }
    }
    r.internal += B.internal[l];
    r.hourglass += B.hourglass[l];
    r.part_internal[static_cast<size_t>(st.part_slot[k])] += B.internal[l];
    r.part_hourglass[static_cast<size_t>(st.part_slot[k])] += B.hourglass[l];
    r.damping_power += B.damping_power[l];
  }
}

// Elements [first, last) of the deformable list: gather, kernel, then each
// corner force added to its node if the node is this block's own (direct),
// else written to the element's slot for the gather; energy partials and
// the first inverted element into r.
void hex8_block(const Model& m, Hex8State& st, const std::vector<Vec3>& x, const std::vector<Vec3>& v, double dt,
                size_t first, size_t last, std::vector<Vec3>& f, BlockResult& r) {
  r.reset();
  Hex8Batch B;
  for (size_t k0 = first; k0 < last;) {
    // A batch of one kind: it ends where the tetrahedra begin.
    const bool tets = k0 >= st.first_tet;
    const size_t end = tets ? last : std::min(last, st.first_tet);
    const int n = static_cast<int>(std::min(kHex8Lanes, end - k0));
    if (tets)
      solid_batch<true>(m, st, x, v, dt, k0, n, B, f, r);
    else
      solid_batch<false>(m, st, x, v, dt, k0, n, B, f, r);
    k0 += static_cast<size_t>(n);
  }
}

}  // namespace

void hex8_forces(const Model& m, Hex8State& st, const std::vector<Vec3>& x, const std::vector<Vec3>& v, double dt,
                 std::vector<Vec3>& f, ElementWork& w, ThreadPool* pool) {
  const size_t n = st.elements.size();
  if (n == 0) return;
  // Every block of elements: its own nodes directly, the shared ones' slots.
  run_blocks(st.blocks.size(), pool, [&](size_t b) {
    hex8_block(m, st, x, v, dt, b * st.block, std::min(n, (b + 1) * st.block), f, st.blocks[b]);
  });
  double volume = 0.0;
  if (const long bad = sum_blocks(st.blocks, w, &volume); bad >= 0) {
    const SolidElement& el = m.solids[static_cast<size_t>(st.elements[static_cast<size_t>(bad)])];
    throw InvertedElement("solid element " + std::to_string(el.id) + " (part " + std::to_string(el.part) + ")",
                          "volume " + std::to_string(volume) + " m³");
  }
  note_loop_limit(st.blocks, 1, [&](long k) { return static_cast<long>(st.elements[static_cast<size_t>(k)]); }, w);
  // The nodes shared between blocks sum their elements' forces in element order.
  st.gather.add_to(st.force, f, pool);
}

}  // namespace fe
