// Eight-node hexahedron with one-point integration and Flanagan–Belytschko
// hourglass control (Flanagan & Belytschko 1981, IJNME 17:679; as used in
// LS-DYNA ELFORM 1 with viscous hourglass control, IHQ 1).
//
// Gradients at the centre: J = Σ_a x_a ⊗ ∂N_a/∂ξ(0), ∂N_a/∂x = J⁻ᵀ·∂N_a/∂ξ(0),
// V = 8·det J. Any linear velocity field v = G·x gives Σ_a v_a ⊗ ∂N_a/∂x = G
// exactly for any element shape (Σ_a x_a ⊗ ∂N_a/∂ξ is J itself), so
// constant strain rates are reproduced: the patch test.
//
// Hourglass: with the base vectors h_α (α = 1..4) the FB shape vectors
//   γ_α = h_α − Σ_i (h_α·x_i)·b_i       (orthogonal to linear fields)
// give the hourglass rates q_αi = Σ_a v_ai·γ_αa and the resisting force
//   f_ai = −c_h·Σ_α q_αi·γ_αa,   c_h = Q_h·ρ·c·V^(2/3)/4,
// which does no work on rigid motions or constant strain rates.
// Node order is LS-DYNA's: 1-2-3-4 one face, 5-6-7-8 the opposite face.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "elements/element_blocks.hpp"
#include "elements/element_work.hpp"
#include "model/model.hpp"

namespace fe {

using Mat83 = Eigen::Matrix<double, 8, 3>;

// The element's rows of a nodal array (coordinates or velocities), 8×3.
Mat83 hex8_gather(const std::vector<Vec3>& a, const SolidElement& e);

// Gradients b (8×3) and volume of the element with node coordinates x (8×3).
// Returns false for a degenerate or inverted element (det J ≤ 0).
bool hex8_gradients(const Mat83& x, Mat83& b, double& volume);

// FB hourglass shape vectors γ (4×8) for gradients b and coordinates x.
Eigen::Matrix<double, 4, 8> hex8_hourglass_shapes(const Mat83& x, const Mat83& b);

// Characteristic length (volume / largest face area): the bulk viscosity's length.
double hex8_characteristic_length(const Mat83& x, double volume);

// Stable step of one element on its own lumped corner masses ρV/8, which
// bounds the mesh's (Irons and Treharne: the largest eigenfrequency of an
// assembly does not exceed its elements' largest). With one-point
// integration K_e = V·Bᵀ·D·B, so ω_max² = (8/ρ)·λ_max(D·B·Bᵀ), a 6×6
// eigenproblem, and Δt = 2/ω_max. It is then reduced for the linear bulk
// viscosity Q2 as LS-DYNA's theory manual does: Δt·(sqrt(1 + Q2²) − Q2).
// For a cube of edge L this is L/c at ν = 0 but 0.73·L/c at ν = 0.3: the
// volume/face-area length alone (L/c) lets a corner node's breathing mode
// run at ω·Δt > 2. Returns 0 for an inverted element.
double hex8_stable_step(const Mat83& x, double lambda, double mu, double rho, double q2, double beta = 0.0);

// The same for any element of N nodes with constant gradients b (N×3) on
// lumped masses ρV/N: ω_max² = (N/ρ)·λ_max(D·B·Bᵀ) (N = 8: the hexahedron
// at its centre; N = 4: the tetrahedron, element_tet4.hpp).
template <int N>
double stable_step_of_gradients(const Eigen::Matrix<double, N, 3>& b, double lambda, double mu, double rho, double q2,
                                double beta = 0.0);

// The hex8 elements' state in the solver: stress per element, and what is
// resolved once for the deformable elements, in their order (`elements`):
// material constants as arrays, each element's slot for its nodal forces
// and the gather (element_blocks.hpp).
struct Hex8State {
  std::vector<Eigen::Matrix<double, 6, 1>> sigma;  // Voigt: xx, yy, zz, xy, yz, zx; per solid
  std::vector<double> plastic_strain;                    // effective plastic strain, per solid
  std::vector<Eigen::Matrix<double, 6, 1>> back_stress;  // kinematic hardening's centre, per solid
  std::vector<int> elements;  // the elements of deformable parts: hexahedra, then tetrahedra
  size_t first_tet = 0;       // where the tetrahedra begin in `elements`
  // What the kernel needs of a part: its material's constants.
  struct PartConstants {
    double lambda = 0.0, two_mu = 0.0, rho = 0.0, wave_speed = 0.0;
    double beta = 0.0;  // the part's stiffness damping β, s (Part::stiffness_damping)
    const Material* plastic = nullptr;  // the plastic material, nullptr if elastic
  };
  std::vector<PartConstants> parts;  // by part slot (element_blocks.hpp)
  // Per deformable element k (index into `elements`), compact for the
  // element loop (which streams them every step):
  std::vector<std::array<int, 8>> nodes;  // its nodes
  std::vector<double> hourglass;  // Q_h·ρ·c·V0^(2/3)/4, fixed per element (V changes little)
  std::vector<double> step_per_length;  // its initial stable step over its initial V/A_max (s/m)
  std::vector<int> part_slot;             // its part's dense index (element_blocks.hpp)
  std::vector<double> force;      // 24 per element: the nodal forces of the last step
  NodalGather gather;
  std::vector<BlockResult> blocks;
  size_t block = 0;  // elements per block: hex8_block_size
  // owner: the elements' ranks (partition.hpp); only those of `rank` are
  // computed here. nullptr: every element.
  explicit Hex8State(const Model& m, const std::vector<int>* owner = nullptr, int rank = 0);
};

// Elements per task of the element loop, processed as batches of
// kHex8Lanes elements side by side (a vectorisable kernel). Large blocks
// keep most nodes inside one block (added directly, element_blocks.hpp:
// 2048 against 256 measured 1.15× faster per element-cycle at 2.6k–10.7k
// hexes and 1.4× at 33.6k, bench_fe hex8); a model of more than 2048
// elements gets at least 8 blocks for the threads. (4096 gained another
// ~1.1× on one thread at 33.6k, but its 8 blocks left the second thread
// idle behind any interruption: the same time on 2 threads.) Depends on
// the element count only, never on the thread count: the sums stay
// bit-identical for any count.
// Stiffness damping (Part::stiffness_damping): the damping stress
// g = β·C:D of the strain rate d (Voigt xx yy zz xy yz zx, tensor shears),
// which the forces carry on top of the stress and which is not stored;
// returns its power per volume g:D (shears counted twice). β = 0: g = 0.
inline double stiffness_damping_stress(double beta, double lambda, double two_mu, const double d[6], double g[6]) {
  const double la = lambda * (d[0] + d[1] + d[2]);
  for (int c = 0; c < 3; ++c) g[c] = beta * (la + two_mu * d[c]);
  for (int c = 3; c < 6; ++c) g[c] = beta * two_mu * d[c];
  return g[0] * d[0] + g[1] * d[1] + g[2] * d[2] + 2.0 * (g[3] * d[3] + g[4] * d[4] + g[5] * d[5]);
}

constexpr size_t kHex8Lanes = 8;
size_t hex8_block_size(size_t elements);

// One batch of kHex8Lanes solids side by side: every array is [..][lane],
// and every loop over lanes is a vector operation. Lanes past the end of
// the element list carry a unit cube at rest and are ignored. A batch is
// all hexahedra or all tetrahedra (element_tet4.hpp: its corners in slots
// 0, 1, 2 and 4, the only slots its kernel reads and writes).
struct SolidBatch {
  static constexpr int W = static_cast<int>(kHex8Lanes);
  double x[8][3][W], v[8][3][W];
  double lambda[W], two_mu[W], rho[W], c[W], ch[W], beta[W], sig[6][W];
  double spl[W];    // the element's stable step per unit of its characteristic length (idle lanes: huge)
  double limit[W];  // out: its current stable step
  // Plastic lanes: their material (nullptr: elastic), effective plastic
  // strain and back stress, updated in place.
  const Material* plastic[W];
  double ep[W], alpha[6][W];
  // Out:
  double f[8][3][W], volume[W], internal[W], hourglass[W], damping_power[W];
  bool any_damped = false;  // a lane with stiffness damping (beta ≠ 0): the damped kernel
};

// One step of every hex8: stress update over dt from the velocities v
// (hypoelastic with the Jaumann rate, J2 plasticity where the material has
// it, bulk viscosity, FB hourglass), forces added to f, energy
// increments to w. Blocks of elements run on the pool's threads (nullptr:
// this thread); the result does not depend on the thread count. Throws
// InvertedElement.
void hex8_forces(const Model& m, Hex8State& s, const std::vector<Vec3>& x, const std::vector<Vec3>& v, double dt,
                 std::vector<Vec3>& f, ElementWork& w, class ThreadPool* pool);

}  // namespace fe
