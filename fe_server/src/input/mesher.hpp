// Mesher for bodies of revolution: a table of axial sections (length, outer
// radius, inner radius) becomes an eight-node hexahedral mesh in the keyword
// format fe_server reads, so a stepped piston or a tool needs no
// pre-processor.
//
// Cross-section: an O-grid, a square core with rings around it. Every
// distinct radius of the table is a ring boundary, so each section takes
// exactly the cells between its inner and outer radius, and the meshes of
// neighbouring sections share their nodes. The axis is z.
//
// Every exposed face normal to the axis (the end faces and the annular steps
// between sections) becomes a *SET_SEGMENT whose node order points out of
// the body, listed with its z and radii in a comment.
//
// mesh_axisymmetric meshes the same table in 2D (quads in the x–y plane) for
// the axisymmetric solid: a hundredth of the hex8 mesh's cost.
#pragma once

#include <string>
#include <vector>

namespace fe {

struct RevolutionSection {
  double length = 0.0, r_out = 0.0, r_in = 0.0;  // m
};

struct RevolutionMeshOptions {
  double element_size = 0.005;  // target edge length, m
  double axial_size = 0.0;      // element length along the axis (0: element_size), e.g. coarse for a rigid body
  double z0 = 0.0;              // z of the first section's start
  int part = 1;
  int node_offset = 0, element_offset = 0, set_offset = 0;  // ids start after these
  std::string title = "body of revolution";
  std::vector<double> gauges;  // z of strain-gauge layers: their elements go to *DATABASE_HISTORY_SOLID
  double radial_growth = 1.0;  // mesh_axisymmetric: ratio of neighbouring radial cells (1: uniform)
  bool gauge_cut_only = false; // mesh_axisymmetric: a gauge writes its cross section only, not its elements' stresses
  std::vector<double> radii;   // mesh_axisymmetric: extra radial cell boundaries (to meet another body's nodes)
};

struct FaceSet {
  int id;
  double z;
  int direction;  // −1 facing −z, +1 facing +z
  double r_in, r_out;
};

struct RevolutionMesh {
  std::string keyword_text;  // *NODE, *ELEMENT_SOLID, *SET_SEGMENT blocks
  int nodes = 0, elements = 0;
  std::vector<FaceSet> faces;
};

// Throws std::invalid_argument for a bad table (non-positive length, r_in ≥ r_out).
RevolutionMesh mesh_revolution(const std::vector<RevolutionSection>& sections, const RevolutionMeshOptions& opt);

// The same table as 2D axisymmetric quads in LS-DYNA's convention: x the
// radius, y the axis (opt.z0 is then the y of the first section's start);
// *ELEMENT_SHELL counter-clockwise, for a part with *SECTION_SHELL ELFORM 15.
// Radial cell boundaries: 0 (for a solid section), every radius of the
// table, and cells of about element_size between them (`radial_growth` > 1
// grades them, each cell that much wider than the one inside it). Faces
// normal to the axis become *SET_SEGMENT sets of 2-node lines (the body on
// their left, so the normal points out), their nodes a *SET_NODE_LIST
// numbered the segment set's id + 20; gauge layers go to
// *DATABASE_HISTORY_SHELL (unless gauge_cut_only), with a
// *DATABASE_CROSS_SECTION_SET through each layer's lower edge (id set offset
// + 100 + gauge number); each section's outer surface nodes become a
// *SET_NODE_LIST numbered set offset + section number.
RevolutionMesh mesh_axisymmetric(const std::vector<RevolutionSection>& sections, const RevolutionMeshOptions& opt);

// Parse "L,ro,ri; L,ro,ri; ..." (ri may be omitted; '/' may replace ';').
std::vector<RevolutionSection> parse_sections(const std::string& text);

}  // namespace fe
