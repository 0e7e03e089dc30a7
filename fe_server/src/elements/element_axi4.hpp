// Four-node axisymmetric solid in LS-DYNA's 2D conventions: nodes in the
// x–y plane, x the radius r ≥ 0 and y the axis of symmetry (*SECTION_SHELL
// ELFORM 15 "volume weighted"; ELFORM 14 decks are read as 15, see
// deck_reader.cpp). Node order 1-2-3-4 counter-clockwise in the (r, y)
// plane (positive area), as LS-DYNA requires.
//
// Everything is per full ring (2π), not per radian: masses, forces and
// volumes are those of the body of revolution, so a cavity pressure p on a
// ring of area 2π·r̄·L, a contact force or a port force is the physical one.
//
// Integration: one point at the element centre with Flanagan–Belytschko
// viscous hourglass control, the same scheme as the hex8 (element_hex8.hpp):
//   b_a = ∂N_a/∂(r, y) at ξ = η = 0,   A = 4·det J (exact for a bilinear quad),
//   r_c = Σ r_a/4 = r(0),  V = 2π·r_c·A,
//   D_rr, D_yy, D_ry from b; hoop D_θθ = v_r(0)/r_c = Σ v_ra/(4·r_c).
// A linear velocity field v_r = a·r + ..., v_y = ... gives the exact constant
// D including the hoop term (D_θθ = a), for any quad shape: the patch test.
// Work conjugate forces of the one-point rule, P = V·σ:D:
//   f_ar = −V·(σ_rr·b_ar + σ_ry·b_ay) − V·σ_θθ/(4·r_c),
//   f_ay = −V·(σ_ry·b_ar + σ_yy·b_ay).
// Why one point and not selective reduced integration (2×2 points for the
// deviatoric part, the centre's volumetric rate at each, no hourglass
// control): measured on the Ø60 mm bar impact (tests/fe_server/
// test_axisymmetric.cpp, h = 2.5 mm, ν = 0.3), both give the same answer —
// plateau −161.16 / −160.99 MPa (theory −162.4), rise 12.9 / 13.2 µs, pulse
// energy W 98.21 / 98.17 % of the piston's — and selective reduced
// integration cost 2.5× the time. The one-point rule's hourglass viscosity
// takes 0.5 % of the impact energy at this mesh (0.3 % at h/2), about what
// bulk viscosity takes in both. Its one zero-energy mode
// (h = (1, −1, 1, −1)) is held by that viscosity.
// Nodes on the axis (r = 0) need no special case: r_c > 0 for any element
// of positive area, and their radial motion is fixed by the reader.
//
// Lumped masses are the consistent row sums m_a = ρ·2π·∫N_a·r dA, exact
// with 2×2 Gauss points (N_a·r·det J is at most cubic in each coordinate),
// so a node on the axis gets its true share, not zero.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "elements/element_blocks.hpp"
#include "elements/element_work.hpp"
#include "model/model.hpp"

namespace fe {

using Mat42 = Eigen::Matrix<double, 4, 2>;

struct Axi4Geometry {
  Mat42 b;           // ∂N_a/∂(r, y) at the centre
  double area = 0;   // A, m²
  double r_c = 0;    // radius of the centre, m
  double volume = 0; // 2π·r_c·A, m³
};

// The element's (x, y) = (r, axial) rows of a nodal array, 4×2.
Mat42 axi4_gather(const std::vector<Vec3>& a, const AxiElement& e);

// Centre gradients, area, radius and ring volume of the element with node
// coordinates x (4×2: r, y). False for a degenerate or clockwise element
// (det J ≤ 0) or one whose centre lies on the axis.
bool axi4_geometry(const Mat42& x, Axi4Geometry& g);

// Lumped nodal masses ρ·2π·∫N_a·r dA (exact), kg.
Eigen::Vector4d axi4_lumped_masses(const Mat42& x, double rho);

// FB hourglass shape vector γ = h − (h·x_i)·b_i, h = (1, −1, 1, −1).
Eigen::Vector4d axi4_hourglass_shape(const Mat42& x, const Mat42& b);

// Hourglass viscosity c_h = Q_h·ρ·c·(2π·r_c·√A)/4: the hex8's Q_h·ρ·c·V^(2/3)/4
// with the ring's face area 2π·r_c·√A for V^(2/3).
double axi4_hourglass_coefficient(const Axi4Geometry& g, double qh, double rho, double wave_speed);

// Bulk viscosity length: area over the longer diagonal.
double axi4_characteristic_length(const Mat42& x, double area);

// Stable step of the element on its own lumped masses (Irons and Treharne, as
// for the hex8): Δt = 2/ω_max with ω_max² = λ_max(M⁻¹·K), K = V·Bᵀ·D·B over
// the rr, yy, ry and θθ strains, DOFs in `fixed_r` (nodes on the axis)
// removed; then reduced for the linear bulk viscosity Q2 and the part's
// stiffness damping β (damped_stable_step). 0 if degenerate.
double axi4_stable_step(const Mat42& x, double lambda, double mu, double rho, double q2,
                        const bool fixed_r[4], double beta = 0.0);

// Elements per task, and per batch of the kernel (side by side in vector lanes).
constexpr size_t kAxi4Block = 512, kAxi4Lanes = 8;

// The axisymmetric elements' state in the solver: stress per element and
// what is resolved once, so the element loop does no lookups; per
// deformable element its force slot (8 doubles: r and y of each corner), the
// gather and the block partials (element_blocks.hpp).
struct Axi4State {
  struct Constants {
    double lambda, mu, rho, wave_speed;
    double hourglass;  // axi4_hourglass_coefficient of the initial shape
    double beta;       // its part's stiffness damping β, s (0: none)
    const Material* plastic;  // the plastic material, nullptr if elastic
  };
  std::vector<Eigen::Matrix<double, 6, 1>> sigma;  // rr, yy (axial), θθ (hoop), ry, 0, 0
  std::vector<double> plastic_strain;                    // effective plastic strain per element
  std::vector<Eigen::Matrix<double, 6, 1>> back_stress;  // kinematic hardening's centre, as sigma
  std::vector<int> elements;                       // the elements of deformable parts
  std::vector<int> part_slot;                      // per deformable element: its part's dense index
  std::vector<Constants> constants;                // per element of the model
  // Per batch of kAxi4Lanes deformable elements (in `elements` order): their
  // nodes and constants side by side as the kernel reads them, so a batch's
  // gather is the nodal state only. Lanes past the end: no nodes, zeros.
  struct Lanes {
    int node[4][kAxi4Lanes];
    double lambda[kAxi4Lanes], two_mu[kAxi4Lanes], rho[kAxi4Lanes], c[kAxi4Lanes], ch[kAxi4Lanes];
    double beta[kAxi4Lanes];  // stiffness damping β (idle lanes: 0)
    // Its initial stable step over its initial characteristic length (s/m):
    // the step it allows later is this times its length then. Idle: huge.
    double spl[kAxi4Lanes];
    int count;         // lanes in use
    bool any_plastic;  // a lane of a plastic material
    bool any_damped;   // a lane with stiffness damping
  };
  std::vector<Lanes> lanes;
  std::vector<double> force;
  NodalGather gather;
  std::vector<BlockResult> blocks;
  // owner: as Hex8State's.
  explicit Axi4State(const Model& m, const std::vector<int>* owner = nullptr, int rank = 0);
};

// One step of every axisymmetric element: the formulas above (the stress on
// the Jaumann rate, J2 plasticity where the material has it) in batches of
// kAxi4Lanes elements (the 2×2 Jacobian's inverse and the centre gradients
// in closed form; an AVX2-cloned kernel; measured: bench_fe, axi4). Forces
// added to f, energy increments to w; blocks on the pool's threads, the
// result independent of the thread count. Throws InvertedElement.
void axi4_forces(const Model& m, Axi4State& s, const std::vector<Vec3>& x, const std::vector<Vec3>& v, double dt,
                 std::vector<Vec3>& f, ElementWork& w, class ThreadPool* pool);

}  // namespace fe
