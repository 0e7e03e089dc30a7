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

Mat42 axi4_gather(const std::vector<Vec3>& a, const AxiElement& e) {
  Mat42 out;
  for (int k = 0; k < 4; ++k) {
    const Vec3& p = a[static_cast<size_t>(e.n[k])];
    out(k, 0) = p.x(), out(k, 1) = p.y();
  }
  return out;
}

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

Axi4State::Axi4State(const Model& m)
    : sigma(m.axis.size(), Eigen::Matrix<double, 6, 1>::Zero()), constants(m.axis.size()) {
  for (size_t e = 0; e < m.axis.size(); ++e) {
    const AxiElement& el = m.axis[e];
    const Material& mat = m.materials.at(m.parts.at(el.part).material);
    if (!mat.rigid) elements.push_back(static_cast<int>(e));
    Axi4Geometry g;
    axi4_geometry(axi4_gather(m.x0, el), g);
    constants[e] = {mat.lambda(), mat.mu(), mat.rho, mat.wave_speed(),
                    axi4_hourglass_coefficient(g, m.hourglass_q, mat.rho, mat.wave_speed())};
  }
}

void axi4_forces(const Model& m, Axi4State& st, const std::vector<Vec3>& x_, const std::vector<Vec3>& v_, double dt_,
                 std::vector<Vec3>& f_int_, ElementWork& w) {
  using Voigt = Eigen::Matrix<double, 6, 1>;
  constexpr double kXi[4] = {-1, 1, 1, -1}, kEta[4] = {-1, -1, 1, 1}, kH[4] = {1, -1, 1, -1};
  constexpr double kTwoPi = 6.283185307179586;
  const double q1 = m.bulk_q1, q2 = m.bulk_q2;
  for (int ei : st.elements) {
    const size_t e = static_cast<size_t>(ei);
    const AxiElement& el = m.axis[e];
    const Axi4State::Constants& k = st.constants[e];
    double r[4], y[4], vr[4], vy[4];
    for (int a = 0; a < 4; ++a) {
      const size_t n = static_cast<size_t>(el.n[a]);
      r[a] = x_[n].x(), y[a] = x_[n].y(), vr[a] = v_[n].x(), vy[a] = v_[n].y();
    }
    const double J00 = 0.25 * (-r[0] + r[1] + r[2] - r[3]), J01 = 0.25 * (-r[0] - r[1] + r[2] + r[3]);
    const double J10 = 0.25 * (-y[0] + y[1] + y[2] - y[3]), J11 = 0.25 * (-y[0] - y[1] + y[2] + y[3]);
    const double det = J00 * J11 - J01 * J10;
    const double r_c = 0.25 * (r[0] + r[1] + r[2] + r[3]);
    if (!(det > 0.0) || !(r_c > 0.0))
      throw InvertedElement("axisymmetric element " + std::to_string(el.id) + " (part " + std::to_string(el.part) + ")",
                            "area " + std::to_string(4.0 * det) + " m²");
    const double inv = 0.25 / det, area = 4.0 * det, volume = kTwoPi * r_c * area;
    double br[4], by[4];
    double d_rr = 0.0, d_yy = 0.0, l_ry = 0.0, l_yr = 0.0, hr = 0.0, hy = 0.0;
    for (int a = 0; a < 4; ++a) {
      br[a] = (kXi[a] * J11 - kEta[a] * J10) * inv;
      by[a] = (kEta[a] * J00 - kXi[a] * J01) * inv;
      d_rr += vr[a] * br[a], d_yy += vy[a] * by[a];
      l_ry += vr[a] * by[a], l_yr += vy[a] * br[a];
      hr += kH[a] * r[a], hy += kH[a] * y[a];
    }
    const double d_ry = 0.5 * (l_ry + l_yr);
    const double d_tt = 0.25 * (vr[0] + vr[1] + vr[2] + vr[3]) / r_c;
    const double trD = d_rr + d_yy + d_tt;
    Voigt& sig = st.sigma[e];
    const double o0 = sig(0), o1 = sig(1), o2 = sig(2), o3 = sig(3);
    const double lt = k.lambda * trD;
    sig(0) += dt_ * (lt + 2 * k.mu * d_rr);
    sig(1) += dt_ * (lt + 2 * k.mu * d_yy);
    sig(2) += dt_ * (lt + 2 * k.mu * d_tt);
    sig(3) += dt_ * 2 * k.mu * d_ry;
    double q = 0.0;  // bulk viscosity in compression, as for the hex8
    if (trD < 0.0) {
      const double dx1 = r[2] - r[0], dy1 = y[2] - y[0], dx2 = r[3] - r[1], dy2 = y[3] - y[1];
      const double len = area / std::sqrt(std::max(dx1 * dx1 + dy1 * dy1, dx2 * dx2 + dy2 * dy2));
      q = k.rho * len * (q1 * len * trD * trD - q2 * k.wave_speed * trD);
    }
    const double s_rr = sig(0) - q, s_yy = sig(1) - q, s_tt = sig(2) - q, s_ry = sig(3);
    // Hourglass (viscous FB), one mode: γ = h − (h·r)·b_r − (h·y)·b_y.
    double gamma[4], qr = 0.0, qy = 0.0;
    for (int a = 0; a < 4; ++a) {
      gamma[a] = kH[a] - hr * br[a] - hy * by[a];
      qr += gamma[a] * vr[a], qy += gamma[a] * vy[a];
    }
    const double hoop = volume * s_tt * 0.25 / r_c;
    for (int a = 0; a < 4; ++a) {
      Vec3& f = f_int_[static_cast<size_t>(el.n[a])];
      f.x() -= volume * (s_rr * br[a] + s_ry * by[a]) + hoop + k.hourglass * gamma[a] * qr;
      f.y() -= volume * (s_ry * br[a] + s_yy * by[a]) + k.hourglass * gamma[a] * qy;
    }
    const double sd = 0.5 * ((o0 + sig(0)) * d_rr + (o1 + sig(1)) * d_yy + (o2 + sig(2)) * d_tt) + (o3 + sig(3)) * d_ry;
    w.internal += volume * sd * dt_;
    w.hourglass += k.hourglass * (qr * qr + qy * qy) * dt_;
    w.damping_power += -q * trD * volume;
  }
}

}  // namespace fe
