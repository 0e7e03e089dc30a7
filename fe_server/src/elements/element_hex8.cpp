#include "elements/element_hex8.hpp"

#include <Eigen/Geometry>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <algorithm>

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

double hex8_stable_step(const Mat83& x, double lambda, double mu, double rho, double q2) {
  Mat83 b;
  double volume = 0.0;
  if (!hex8_gradients(x, b, volume)) return 0.0;
  // B (6×24, engineering shear) and the 6×6 product B·Bᵀ.
  Eigen::Matrix<double, 6, 24> B = Eigen::Matrix<double, 6, 24>::Zero();
  for (int a = 0; a < 8; ++a) {
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
  const double omega = std::sqrt(8.0 * lmax / rho);
  return 2.0 / omega * (std::sqrt(1.0 + q2 * q2) - q2);
}

Mat83 hex8_gather(const std::vector<Vec3>& a, const SolidElement& e) {
  Mat83 out;
  for (int k = 0; k < 8; ++k) out.row(k) = a[static_cast<size_t>(e.n[k])].transpose();
  return out;
}

Hex8State::Hex8State(const Model& m)
    : sigma(m.solids.size(), Eigen::Matrix<double, 6, 1>::Zero()),
      material(m.solids.size()),
      hourglass(m.solids.size()) {
  for (size_t e = 0; e < m.solids.size(); ++e) {
    const SolidElement& el = m.solids[e];
    const Material& mat = m.materials.at(m.parts.at(el.part).material);
    if (!mat.rigid) elements.push_back(static_cast<int>(e));
    material[e] = &mat;
    Mat83 b;
    double volume = 0.0;
    hex8_gradients(hex8_gather(m.x0, el), b, volume);
    hourglass[e] = m.hourglass_q * mat.rho * mat.wave_speed() * std::cbrt(volume * volume) / 4.0;
  }
}

void hex8_forces(const Model& m, Hex8State& st, const std::vector<Vec3>& x_all, const std::vector<Vec3>& v_all,
                 double dt, std::vector<Vec3>& f_all, ElementWork& w) {
  using Voigt = Eigen::Matrix<double, 6, 1>;
  const double q1 = m.bulk_q1, q2 = m.bulk_q2;
  for (int ei : st.elements) {
    const size_t e = static_cast<size_t>(ei);
    const SolidElement& el = m.solids[e];
    const Material& mat = *st.material[e];
    const Mat83 x = hex8_gather(x_all, el), v = hex8_gather(v_all, el);
    Mat83 b;
    double volume = 0.0;
    if (!hex8_gradients(x, b, volume))
      throw InvertedElement("solid element " + std::to_string(el.id) + " (part " + std::to_string(el.part) + ")",
                            "volume " + std::to_string(volume) + " m³");
    // Rate of deformation D = sym(L), L_ij = Σ_a v_ai b_aj.
    const Eigen::Matrix3d L = v.transpose() * b;
    const Eigen::Matrix3d D = 0.5 * (L + L.transpose());
    const double trD = D.trace();
    const double lambda = mat.lambda(), mu = mat.mu();
    Voigt dsig;
    dsig << lambda * trD + 2 * mu * D(0, 0), lambda * trD + 2 * mu * D(1, 1), lambda * trD + 2 * mu * D(2, 2),
        2 * mu * D(0, 1), 2 * mu * D(1, 2), 2 * mu * D(2, 0);
    Voigt& sig = st.sigma[e];
    const Voigt old = sig;
    sig += dt * dsig;
    // Bulk viscosity in compression (von Neumann–Richtmyer with a linear term, LS-DYNA's Q1, Q2).
    double q = 0.0;
    if (trD < 0.0) {
      const double len = hex8_characteristic_length(x, volume);
      q = mat.rho * len * (q1 * len * trD * trD - q2 * mat.wave_speed() * trD);
    }
    Eigen::Matrix3d s;
    s << sig(0) - q, sig(3), sig(5), sig(3), sig(1) - q, sig(4), sig(5), sig(4), sig(2) - q;
    const Mat83 f = -volume * b * s;  // f_a = −V·σ·b_a
    // Hourglass (viscous FB): f = −c_h Σ_α γ_α ⊗ q_α.
    const Eigen::Matrix<double, 4, 8> gamma = hex8_hourglass_shapes(x, b);
    const Eigen::Matrix<double, 4, 3> qa = gamma * v;
    const double c_h = st.hourglass[e];
    const Mat83 f_hg = -c_h * gamma.transpose() * qa;
    for (int k = 0; k < 8; ++k) f_all[static_cast<size_t>(el.n[k])] += (f.row(k) + f_hg.row(k)).transpose();
    // Energies of this step: elastic σ:D (trapezoidal in σ), hourglass and bulk viscosity dissipation.
    const Voigt mid = 0.5 * (old + sig);
    const double sd = mid(0) * D(0, 0) + mid(1) * D(1, 1) + mid(2) * D(2, 2) +
                      2 * (mid(3) * D(0, 1) + mid(4) * D(1, 2) + mid(5) * D(2, 0));
    w.internal += volume * sd * dt;
    w.hourglass += c_h * qa.squaredNorm() * dt;
    w.damping_power += -q * trD * volume;
  }
}

}  // namespace fe
