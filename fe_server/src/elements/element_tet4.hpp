// Four-node tetrahedron, constant strain (LS-DYNA ELFORM 10): linear shape
// functions, so the gradients are exact and constant over the element and
// one point integrates it exactly; it has no hourglass modes.
//
// With the edges e1 = x2 − x1, e2 = x3 − x1, e3 = x4 − x1 from corner 1:
//   6V = e1·(e2 × e3),  b2 = (e2 × e3)/6V,  b3 = (e3 × e1)/6V,
//   b4 = (e1 × e2)/6V,  b1 = −(b2 + b3 + b4)
// (b_a = ∂N_a/∂x; |b_a| = 1/h_a, h_a the altitude over the face opposite
// corner a). The nodal forces are f_a = −V·σ·b_a and the lumped masses ρV/4.
//
// A tetrahedron is stored as the solids are, eight node slots in LS-DYNA's
// degenerate form n1 n2 n3 n3 n4 n4 n4 n4: its corners are slots 0, 1, 2
// and 4 (kTet4Corners); the other slots get no force and no mass. Corner 4
// lies on the side from which n1 → n2 → n3 turns counter-clockwise (V > 0).
#pragma once

#include <Eigen/Core>

#include "elements/element_hex8.hpp"
#include "model/model.hpp"

namespace fe {

constexpr int kTet4Corners[4] = {0, 1, 2, 4};

// Gradients b (rows: corners 1-4) and volume of the tetrahedron whose eight
// slots are x. Returns false for a flat or inverted one (V ≤ 0).
bool tet4_gradients(const Mat83& x, Eigen::Matrix<double, 4, 3>& b, double& volume);

// Characteristic length: the smallest altitude, 3V over the largest face
// (LS-DYNA's length for tetrahedra); the bulk viscosity's length too.
double tet4_characteristic_length(const Mat83& x);

// Stable step on its lumped masses ρV/4: ω_max² = (4/ρ)·λ_max(D·B·Bᵀ), the
// element's exact largest eigenfrequency (which bounds the mesh's, Irons
// and Treharne), Δt = 2/ω_max, reduced for Q2 as the hexahedron's
// (element_hex8.hpp). For the regular tetrahedron of edge a at ν = 0.3
// this is 0.52·a/c; the smallest altitude over c (0.82·a/c) would be
// unstable. Returns 0 for an inverted element.
double tet4_stable_step(const Mat83& x, double lambda, double mu, double rho, double q2, double beta = 0.0);

// One batch of tetrahedra (the same update as the hexahedra's: Jaumann
// rate, J2 return where plastic, bulk viscosity; no hourglass), forces in
// the batch's slots.
void tet4_kernel(SolidBatch& B, double dt, double q1, double q2);

// What every loop over the solids asks of an element, whichever its kind:
// the volume, each slot's share of the lumped mass (1/8 each for a
// hexahedron; 1/4 at a tetrahedron's corners, 0 at its other slots), the
// stable step and the characteristic length.
double solid_volume(const Mat83& x, const SolidElement& e);
double solid_mass_share(const SolidElement& e, int slot);
double solid_stable_step(const Mat83& x, const SolidElement& e, double lambda, double mu, double rho, double q2,
                         double beta = 0.0);
double solid_characteristic_length(const Mat83& x, const SolidElement& e);

}  // namespace fe
