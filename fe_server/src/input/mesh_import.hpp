// Meshes from meshers as keyword meshes: gmsh's and Abaqus' (below).
//
// A gmsh mesh (.msh, ASCII, format 4.1 or 2.2: what gmsh writes, e.g.
// `gmsh -3 part.geo -format msh41`) as a keyword mesh for *INCLUDE:
//
//   - each physical volume becomes a *PART (PID = the group's tag, its name
//     the title; SECID and MID = PID) with its *SECTION_SOLID: ELFORM 10 for
//     tetrahedra, 1 for hexahedra and prisms (wedges); the including deck
//     gives the materials (*MAT_... with MID = PID). A mesh without
//     physical volumes makes a part of every volume entity instead.
//   - each physical surface becomes a *SET_SEGMENT (SID = its tag) of its
//     triangles and quadrilaterals, ordered so that each segment's normal
//     points out of the solid it bounds (a cavity's pressure pushes into
//     the wall; gmsh orients surfaces as their geometry does), and a
//     *SET_NODE_LIST of its nodes (SID = the same tag): sets for
//     *USER_LOADING_SET, contacts, loads and constraints.
//
// Refused, with the line: binary files, elements other than 4-node
// tetrahedra, 8-node hexahedra, 6-node prisms on volumes and 3- and 4-node
// faces on surfaces (10-node tetrahedra: mesh with Mesh.ElementOrder 1); a
// volume entity in two physical volumes; a surface face that no volume
// element has, or that two have (an inner face has no outside).
#pragma once

#include <string>

namespace fe {

struct GmshDeck {
  std::string keyword_text;
  size_t nodes = 0, tetrahedra = 0, hexahedra = 0, prisms = 0, segments = 0;
  std::string summary;  // one line per part and set
};

// Throws config::InputError (file:line) for what it refuses.
GmshDeck gmsh_to_keywords(const std::string& text, const std::string& name);

// The same from an Abaqus input (.inp, flattened: no *PART/*ASSEMBLY), as
// most meshers write it: *NODE, *ELEMENT (C3D4, C3D8/R/I, C3D6; 3- and
// 4-node face elements), *ELSET (GENERATE too), *SURFACE of element faces
// (S1..), *SOLID SECTION. Parts: the solid sections' element sets; without
// sections the *ELSETs of solids (gmsh's physical volumes), else the sets
// named on *ELEMENT lines; PIDs 1.. in that order, the set's name the title.
// Surfaces: each *SURFACE, then each element set of face elements, SIDs 1..
// in that order. Materials, steps and loads are not converted (listed).
GmshDeck abaqus_to_keywords(const std::string& text, const std::string& name);

}  // namespace fe
