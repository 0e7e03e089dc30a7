#include "elements/element_axi4.hpp"
#include "elements/element_plasticity.hpp"

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

double axi4_stable_step(const Mat42& x, double lambda, double mu, double rho, double q2, const bool fixed_r[4],
                        double beta) {
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
  return damped_stable_step(std::sqrt(lmax), q2, beta);
}

Axi4State::Axi4State(const Model& m, const std::vector<int>* owner, int rank)
    : sigma(m.axis.size(), Eigen::Matrix<double, 6, 1>::Zero()),
      plastic_strain(m.axis.size(), 0.0),
      back_stress(m.axis.size(), Eigen::Matrix<double, 6, 1>::Zero()),
      constants(m.axis.size()) {
  for (size_t e = 0; e < m.axis.size(); ++e) {
    const AxiElement& el = m.axis[e];
    const Part& part = m.parts.at(el.part);
    const Material& mat = m.materials.at(part.material);
    if (!mat.rigid && (!owner || (*owner)[e] == rank)) elements.push_back(static_cast<int>(e)), part_slot.push_back(fe::part_slot(m, el.part));
    Axi4Geometry g;
    axi4_geometry(axi4_gather(m.x0, el), g);
    constants[e] = {mat.lambda(), mat.mu(), mat.rho, mat.wave_speed(),
                    axi4_hourglass_coefficient(g, m.hourglass_q, mat.rho, mat.wave_speed()), part.stiffness_damping,
                    mat.plastic ? &mat : nullptr};
  }
  Lanes idle{};
  std::fill_n(idle.spl, kAxi4Lanes, 1e300);
  lanes.assign((elements.size() + kAxi4Lanes - 1) / kAxi4Lanes, idle);
  for (size_t k = 0; k < elements.size(); ++k) {
    Lanes& L = lanes[k / kAxi4Lanes];
    const size_t l = k % kAxi4Lanes;
    const size_t e = static_cast<size_t>(elements[k]);
    for (int a = 0; a < 4; ++a) L.node[a][l] = m.axis[e].n[a];
    const Constants& c = constants[e];
    L.lambda[l] = c.lambda, L.two_mu[l] = 2.0 * c.mu, L.rho[l] = c.rho, L.c[l] = c.wave_speed, L.ch[l] = c.hourglass;
    L.beta[l] = c.beta;
    {
      const AxiElement& el = m.axis[e];
      const Mat42 x0 = axi4_gather(m.x0, el);
      Axi4Geometry g;
      axi4_geometry(x0, g);
      bool fixed_r[4];
      for (int a = 0; a < 4; ++a) fixed_r[a] = m.fixed[static_cast<size_t>(el.n[a])][0];
      const double len0 = axi4_characteristic_length(x0, g.area);
      const double step0 = axi4_stable_step(x0, c.lambda, c.mu, c.rho * el.mass_scale, m.bulk_q2, fixed_r, c.beta);
      L.spl[l] = len0 > 0.0 && step0 > 0.0 ? step0 / len0 : 1e300;
    }
    L.count = static_cast<int>(l) + 1;
    L.any_plastic = L.any_plastic || c.plastic;
    L.any_damped = L.any_damped || c.beta != 0.0;
  }
  force.assign(8 * elements.size(), 0.0);
  blocks.resize((elements.size() + kAxi4Block - 1) / kAxi4Block);
  for (BlockResult& b : blocks) b.part_internal.assign(m.parts.size(), 0.0), b.part_hourglass.assign(m.parts.size(), 0.0);
  // Every node slotted: direct nodes (element_blocks.hpp) measured 3–4 %
  // slower here (bench_fe axi4, interleaved runs), the quad's two force
  // components being cheap to slot and sum.
  gather.build(m.x0.size(), elements.size(), 4, 2, 0,
               [&](size_t k, int a) { return m.axis[static_cast<size_t>(elements[k])].n[a]; },
               [](int) { return true; });
}

namespace {

constexpr int W = static_cast<int>(kAxi4Lanes);

// A batch of W elements side by side, every array [..][lane]. Idle lanes
// (past the end of the list) carry a unit square at r = 1..2 at rest.
struct Axi4Batch {
  double r[4][W], y[4][W], vr[4][W], vy[4][W];
  double lambda[W], two_mu[W], rho[W], c[W], ch[W], beta[W], sig[4][W];
  double spl[W];  // stable step per unit of characteristic length
  // Plastic lanes (the Plastic kernel only): material (nullptr: elastic),
  // effective plastic strain and back stress (rr, yy, θθ, ry), in place.
  const Material* plastic[W];
  double ep[W], alpha[4][W];
  // Out:
  double fr[4][W], fy[4][W], det[W], r_c[W], internal[W], hourglass[W], damping_power[W];
  double limit[W];  // its current stable step
};

// Plastic: the batch has plastic lanes, which take the radial return
// between the trial stress and the forces (element_plasticity.hpp); the
// elastic instantiation is the vectorised hot path. Damped: the batch has a
// lane with stiffness damping (Part::stiffness_damping); without, the
// kernel is the one it was before damping came in.
template <bool Plastic, bool Damped>
__attribute__((always_inline)) inline void axi4_kernel_impl(Axi4Batch& B, double dt, double q1, double q2) {
  constexpr double kXi[4] = {-1, 1, 1, -1}, kEta[4] = {-1, -1, 1, 1}, kH[4] = {1, -1, 1, -1};
  constexpr double kTwoPi = 6.283185307179586;
  for (int l = 0; l < W; ++l) {
    const double r0 = B.r[0][l], r1 = B.r[1][l], r2 = B.r[2][l], r3 = B.r[3][l];
    const double y0 = B.y[0][l], y1 = B.y[1][l], y2 = B.y[2][l], y3 = B.y[3][l];
    const double J00 = 0.25 * (-r0 + r1 + r2 - r3), J01 = 0.25 * (-r0 - r1 + r2 + r3);
    const double J10 = 0.25 * (-y0 + y1 + y2 - y3), J11 = 0.25 * (-y0 - y1 + y2 + y3);
    const double det = J00 * J11 - J01 * J10;
    const double r_c = 0.25 * (r0 + r1 + r2 + r3);
    B.det[l] = det;
    B.r_c[l] = r_c;
    const bool ok = det > 0.0 && r_c > 0.0;  // a bad lane is reported, its numbers unused
    const double inv = ok ? 0.25 / det : 0.0, area = 4.0 * det, volume = kTwoPi * r_c * area;
    const double inv_rc = ok ? 1.0 / r_c : 0.0;
    double br[4], by[4];
    double d_rr = 0.0, d_yy = 0.0, l_ry = 0.0, l_yr = 0.0, hr = 0.0, hy = 0.0, vr_sum = 0.0;
    for (int a = 0; a < 4; ++a) {
      br[a] = (kXi[a] * J11 - kEta[a] * J10) * inv;
      by[a] = (kEta[a] * J00 - kXi[a] * J01) * inv;
      d_rr += B.vr[a][l] * br[a], d_yy += B.vy[a][l] * by[a];
      l_ry += B.vr[a][l] * by[a], l_yr += B.vy[a][l] * br[a];
      hr += kH[a] * B.r[a][l], hy += kH[a] * B.y[a][l];
      vr_sum += B.vr[a][l];
    }
    const double d_ry = 0.5 * (l_ry + l_yr);
    const double d_tt = 0.25 * vr_sum * inv_rc;
    const double trD = d_rr + d_yy + d_tt;
    const double o0 = B.sig[0][l], o1 = B.sig[1][l], o2 = B.sig[2][l], o3 = B.sig[3][l];
    const double lt = B.lambda[l] * trD, tm = B.two_mu[l];
    // The Jaumann rate's spin in the r–y plane (the hoop stress does not turn).
    const double w = 0.5 * (l_ry - l_yr), turn = 2.0 * w * o3;
    double n0 = o0 + dt * (lt + tm * d_rr + turn), n1 = o1 + dt * (lt + tm * d_yy - turn),
           n2 = o2 + dt * (lt + tm * d_tt), n3 = o3 + dt * (tm * d_ry + w * (o1 - o0));
    if constexpr (Plastic) {
      if (B.plastic[l]) {
        double t[6] = {n0, n1, n2, n3, 0.0, 0.0};
        double a[6] = {B.alpha[0][l], B.alpha[1][l], B.alpha[2][l], B.alpha[3][l], 0.0, 0.0};
        jaumann_rotate(a, w, 0.0, 0.0, dt);
        radial_return(*B.plastic[l], 0.5 * tm, t, a, B.ep[l]);
        n0 = t[0], n1 = t[1], n2 = t[2], n3 = t[3];
        for (int c = 0; c < 4; ++c) B.alpha[c][l] = a[c];
      }
    }
    // Bulk viscosity in compression, as for the hex8 (length: area over the longer diagonal).
    const double dx1 = r2 - r0, dy1 = y2 - y0, dx2 = r3 - r1, dy2 = y3 - y1;
    const double diag2 = std::max(dx1 * dx1 + dy1 * dy1, dx2 * dx2 + dy2 * dy2);
    const double len = diag2 > 0.0 ? area / std::sqrt(diag2) : 0.0;
    B.limit[l] = B.spl[l] * len;
    const double q = trD < 0.0 ? B.rho[l] * len * (q1 * len * trD * trD - q2 * B.c[l] * trD) : 0.0;
    // Stiffness damping β·C:D (Part::stiffness_damping), carried by the
    // forces and not stored: its power V·β·D:C:D is dissipated.
    double s_rr = n0 - q, s_yy = n1 - q, s_tt = n2 - q, s_ry = n3, damping = -q * trD;
    if constexpr (Damped) {
      const double bt = B.beta[l];
      const double g0 = bt * (lt + tm * d_rr), g1 = bt * (lt + tm * d_yy), g2 = bt * (lt + tm * d_tt), g3 = bt * tm * d_ry;
      s_rr += g0, s_yy += g1, s_tt += g2, s_ry += g3;
      damping += g0 * d_rr + g1 * d_yy + g2 * d_tt + 2.0 * g3 * d_ry;
    }
    // Hourglass (viscous FB), one mode: γ = h − (h·r)·b_r − (h·y)·b_y.
    double gamma[4], qr = 0.0, qy = 0.0;
    for (int a = 0; a < 4; ++a) {
      gamma[a] = kH[a] - hr * br[a] - hy * by[a];
      qr += gamma[a] * B.vr[a][l], qy += gamma[a] * B.vy[a][l];
    }
    const double hoop = volume * s_tt * 0.25 * inv_rc, ch = B.ch[l];
    for (int a = 0; a < 4; ++a) {
      B.fr[a][l] = -(volume * (s_rr * br[a] + s_ry * by[a]) + hoop + ch * gamma[a] * qr);
      B.fy[a][l] = -(volume * (s_ry * br[a] + s_yy * by[a]) + ch * gamma[a] * qy);
    }
    const double sd = 0.5 * ((o0 + n0) * d_rr + (o1 + n1) * d_yy + (o2 + n2) * d_tt) + (o3 + n3) * d_ry;
    B.sig[0][l] = n0, B.sig[1][l] = n1, B.sig[2][l] = n2, B.sig[3][l] = n3;
    B.internal[l] = volume * sd * dt;
    B.hourglass[l] = ch * (qr * qr + qy * qy) * dt;
    B.damping_power[l] = damping * volume;
  }
}

__attribute__((target_clones("avx2", "default"))) void axi4_kernel(Axi4Batch& B, double dt, double q1, double q2) {
  axi4_kernel_impl<false, false>(B, dt, q1, q2);
}
__attribute__((target_clones("avx2", "default"))) void axi4_kernel_damped(Axi4Batch& B, double dt, double q1, double q2) {
  axi4_kernel_impl<false, true>(B, dt, q1, q2);
}
void axi4_kernel_plastic(Axi4Batch& B, double dt, double q1, double q2) { axi4_kernel_impl<true, true>(B, dt, q1, q2); }

void axi4_block(const Model& m, Axi4State& st, const std::vector<Vec3>& x, const std::vector<Vec3>& v, double dt,
                size_t first, size_t last, BlockResult& res) {
  res.reset();
  Axi4Batch B;
  for (size_t k0 = first; k0 < last; k0 += kAxi4Lanes) {
    const Axi4State::Lanes& K = st.lanes[k0 / kAxi4Lanes];  // blocks start on a batch boundary
    const int n = K.count;
    for (int a = 0; a < 4; ++a)
      for (int l = 0; l < n; ++l) {
        const Vec3 &p = x[static_cast<size_t>(K.node[a][l])], &u = v[static_cast<size_t>(K.node[a][l])];
        B.r[a][l] = p.x(), B.y[a][l] = p.y(), B.vr[a][l] = u.x(), B.vy[a][l] = u.y();
      }
    std::copy_n(K.lambda, W, B.lambda), std::copy_n(K.two_mu, W, B.two_mu), std::copy_n(K.rho, W, B.rho);
    std::copy_n(K.c, W, B.c), std::copy_n(K.ch, W, B.ch), std::copy_n(K.beta, W, B.beta);
    std::copy_n(K.spl, W, B.spl);
    for (int l = 0; l < n; ++l) {
      const Eigen::Matrix<double, 6, 1>& s = st.sigma[static_cast<size_t>(st.elements[k0 + static_cast<size_t>(l)])];
      for (int c = 0; c < 4; ++c) B.sig[c][l] = s(c);
    }
    for (int l = n; l < W; ++l) {  // idle lanes (the last batch): a unit square at rest, no stress
      for (int a = 0; a < 4; ++a)
        B.r[a][l] = 1.5 + 0.5 * kXi[a], B.y[a][l] = 0.5 + 0.5 * kEta[a], B.vr[a][l] = B.vy[a][l] = 0.0;
      for (int c = 0; c < 4; ++c) B.sig[c][l] = 0.0;
    }
    if (K.any_plastic) {
      for (int l = 0; l < W; ++l) {
        const size_t e = l < n ? static_cast<size_t>(st.elements[k0 + static_cast<size_t>(l)]) : 0;
        B.plastic[l] = l < n ? st.constants[e].plastic : nullptr;
        if (B.plastic[l]) {
          B.ep[l] = st.plastic_strain[e];
          for (int c = 0; c < 4; ++c) B.alpha[c][l] = st.back_stress[e](c);
        }
      }
      axi4_kernel_plastic(B, dt, m.bulk_q1, m.bulk_q2);
    } else {
      (K.any_damped ? axi4_kernel_damped : axi4_kernel)(B, dt, m.bulk_q1, m.bulk_q2);
    }
    note_step_limits(B.limit, W, n, k0, res);
    for (int l = 0; l < n; ++l) {
      const size_t k = k0 + static_cast<size_t>(l);
      if (!(B.det[l] > 0.0 && B.r_c[l] > 0.0) && res.inverted < 0) {
        res.inverted = static_cast<long>(k);
        res.measure = 4.0 * B.det[l];
      }
      const size_t e = static_cast<size_t>(st.elements[k]);
      for (int c = 0; c < 4; ++c) st.sigma[e](c) = B.sig[c][l];
      if (K.any_plastic && B.plastic[l]) {
        st.plastic_strain[e] = B.ep[l];
        for (int c = 0; c < 4; ++c) st.back_stress[e](c) = B.alpha[c][l];
      }
      double* out = &st.force[8 * k];  // every node slotted (the constructor)
      for (int a = 0; a < 4; ++a) out[2 * a] = B.fr[a][l], out[2 * a + 1] = B.fy[a][l];
      res.internal += B.internal[l];
      res.hourglass += B.hourglass[l];
      res.part_internal[static_cast<size_t>(st.part_slot[k])] += B.internal[l];
      res.part_hourglass[static_cast<size_t>(st.part_slot[k])] += B.hourglass[l];
      res.damping_power += B.damping_power[l];
    }
  }
}

}  // namespace

void axi4_forces(const Model& m, Axi4State& st, const std::vector<Vec3>& x, const std::vector<Vec3>& v, double dt,
                 std::vector<Vec3>& f, ElementWork& w, ThreadPool* pool) {
  const size_t n = st.elements.size();
  if (n == 0) return;
  run_blocks(st.blocks.size(), pool, [&](size_t b) {
    axi4_block(m, st, x, v, dt, b * kAxi4Block, std::min(n, (b + 1) * kAxi4Block), st.blocks[b]);
  });
  double area = 0.0;
  if (const long bad = sum_blocks(st.blocks, w, &area); bad >= 0) {
    const AxiElement& el = m.axis[static_cast<size_t>(st.elements[static_cast<size_t>(bad)])];
    throw InvertedElement("axisymmetric element " + std::to_string(el.id) + " (part " + std::to_string(el.part) + ")",
                          "area " + std::to_string(area) + " m²");
  }
  note_loop_limit(st.blocks, 2, [&](long k) { return static_cast<long>(st.elements[static_cast<size_t>(k)]); }, w);
  st.gather.add_to(st.force, f, pool);
}

}  // namespace fe
