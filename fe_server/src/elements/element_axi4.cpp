#include "elements/element_axi4.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace fe {

namespace {
constexpr double kTwoPi = 6.283185307179586;
// Natural coordinates of the 4 nodes, counter-clockwise.
constexpr double kXi[4] = {-1, 1, 1, -1};
constexpr double kEta[4] = {-1, -1, 1, 1};
constexpr double kH[4] = {1, -1, 1, -1};  // the hourglass base vector ξη at the nodes
}  // namespace

bool axi4_geometry(const Mat42& x, Axi4Geometry& g) {
  Mat42 dN;  // ∂N_a/∂(ξ, η) at the centre
  for (int a = 0; a < 4; ++a) dN(a, 0) = kXi[a] / 4.0, dN(a, 1) = kEta[a] / 4.0;
  const Eigen::Matrix2d J = x.transpose() * dN;  // J_ij = Σ_a x_ai ∂N_a/∂ξ_j
  const double det = J.determinant();
  g.area = 4.0 * det;
  g.r_c = 0.25 * x.col(0).sum();
  g.volume = kTwoPi * g.r_c * g.area;
  if (!(det > 0.0) || !(g.r_c > 0.0)) return false;
  g.b = dN * J.inverse();
  return true;
}

Eigen::Vector4d axi4_lumped_masses(const Mat42& x, double rho) {
  Eigen::Vector4d m = Eigen::Vector4d::Zero();
  const double gp = 1.0 / std::sqrt(3.0);
  for (double xi : {-gp, gp})
    for (double eta : {-gp, gp}) {
      double N[4];
      Mat42 dN;
      for (int a = 0; a < 4; ++a) {
        N[a] = 0.25 * (1 + kXi[a] * xi) * (1 + kEta[a] * eta);
        dN(a, 0) = 0.25 * kXi[a] * (1 + kEta[a] * eta);
        dN(a, 1) = 0.25 * kEta[a] * (1 + kXi[a] * xi);
      }
      const double det = (x.transpose() * dN).determinant();
      double r = 0.0;
      for (int a = 0; a < 4; ++a) r += N[a] * x(a, 0);
      for (int a = 0; a < 4; ++a) m(a) += rho * kTwoPi * N[a] * r * det;  // Gauss weights are 1
    }
  return m;
}

Eigen::Vector4d axi4_hourglass_shape(const Mat42& x, const Mat42& b) {
  const Eigen::Vector4d h(kH[0], kH[1], kH[2], kH[3]);
  const Eigen::RowVector2d hx = h.transpose() * x;
  return h - b * hx.transpose();
}

double axi4_hourglass_coefficient(const Axi4Geometry& g, double qh, double rho, double wave_speed) {
  return qh * rho * wave_speed * kTwoPi * g.r_c * std::sqrt(g.area) / 4.0;
}

double axi4_characteristic_length(const Mat42& x, double area) {
  const double d1 = (x.row(2) - x.row(0)).norm(), d2 = (x.row(3) - x.row(1)).norm();
  const double d = std::max(d1, d2);
  return d > 0.0 ? area / d : 0.0;
}

double axi4_stable_step(const Mat42& x, double lambda, double mu, double rho, double q2, const bool fixed_r[4]) {
  Axi4Geometry g;
  if (!axi4_geometry(x, g)) return 0.0;
  // B: rows rr, yy, ry (engineering shear), θθ; columns r and y of each node.
  Eigen::Matrix<double, 4, 8> B = Eigen::Matrix<double, 4, 8>::Zero();
  for (int a = 0; a < 4; ++a) {
    B(0, 2 * a) = g.b(a, 0);
    B(1, 2 * a + 1) = g.b(a, 1);
    B(2, 2 * a) = g.b(a, 1), B(2, 2 * a + 1) = g.b(a, 0);
    B(3, 2 * a) = 0.25 / g.r_c;
  }
  Eigen::Matrix4d D = Eigen::Matrix4d::Zero();
  for (int i : {0, 1, 3})
    for (int j : {0, 1, 3}) D(i, j) = lambda + (i == j ? 2.0 * mu : 0.0);
  D(2, 2) = mu;
  Eigen::Matrix<double, 8, 8> K = g.volume * B.transpose() * D * B;
  const Eigen::Vector4d m = axi4_lumped_masses(x, rho);
  // M^(-1/2)·K·M^(-1/2), the DOFs fixed on the axis left out.
  Eigen::Matrix<double, 8, 1> s;
  for (int a = 0; a < 4; ++a) {
    if (!(m(a) > 0.0)) return 0.0;
    s(2 * a) = fixed_r[a] ? 0.0 : 1.0 / std::sqrt(m(a));
    s(2 * a + 1) = 1.0 / std::sqrt(m(a));
  }
  const Eigen::Matrix<double, 8, 8> S = s.asDiagonal() * K * s.asDiagonal();
  const double lmax =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 8, 8>>(S, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
  if (!(lmax > 0.0)) return 0.0;
  return 2.0 / std::sqrt(lmax) * (std::sqrt(1.0 + q2 * q2) - q2);
}

}  // namespace fe
