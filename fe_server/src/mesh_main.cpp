// fe_mesh: bodies of revolution → keyword mesh (nodes, elements, face sets);
// or a gmsh mesh or an Abaqus input → keyword mesh (input/mesh_import.hpp).
//
//   fe_mesh --from-gmsh part.msh -o mesh.k
//   fe_mesh --sections "L,ro[,ri]; L,ro[,ri]; ..." [--size h] [--part PID] [--z0 Z]
//           [--node-offset N] [--element-offset E] [--set-offset S] [--title T]
//           [--gauge Z ...] [--axisymmetric [--radial-growth G] [--gauge-cut-only] [--radius R ...]] -o mesh.k
// Include the result from a deck (*INCLUDE) that defines the part's *PART,
// *SECTION_SOLID (hex8) or *SECTION_SHELL ELFORM 15 (--axisymmetric: quads
// in the x–y plane, y the axis; --z0 and --gauge are then along y) and material.
// An axisymmetric gauge writes its layer's stresses and a cross section
// through it (force and mean velocity); --gauge-cut-only keeps the section
// alone (a long run's output). --radius adds a radial cell boundary (to put
// a node where another body's edge rests, e.g. a tool's top face under a
// piston and a stop ring).
#include <fstream>
#include <iostream>
#include <string>

#include "config/cli.hpp"
#include "config/version.hpp"
#include "config/keyword_reader.hpp"
#include "input/mesh_import.hpp"
#include "input/mesher.hpp"

namespace {

const char* kUsage =
    "usage: fe_mesh --sections \"L,ro[,ri]/L,ro[,ri]/...\" -o mesh.k [options]\n"
    "       fe_mesh --from-gmsh part.msh -o mesh.k    (or --from-abaqus part.inp)\n"
    "  --from-gmsh FILE    a gmsh mesh (ASCII .msh 4.1 or 2.2, e.g. gmsh -3 part.geo): physical volumes\n"
    "                      become parts (PID = tag; tetrahedra ELFORM 10, hexahedra and prisms ELFORM 1),\n"
    "                      physical surfaces segment and node sets (SID = tag, segments facing out);\n"
    "                      the including deck gives the materials (MID = PID)\n"
    "  --from-abaqus FILE  the same from an Abaqus .inp (flattened): solid sections' or solids' element\n"
    "                      sets become parts, *SURFACEs and sets of face elements segment and node sets\n"
    "  --sections T        the body's sections from z0 up: length, outer radius and optional inner\n"
    "                      radius, in metres; sections separated by '/' (or ';')\n"
    "  -o FILE             the keyword mesh to write (*NODE, elements, face and node sets)\n"
    "  --size H            radial (and, without --axial-size, axial) cell size (default 0.005 m)\n"
    "  --axial-size H      axial cell size\n"
    "  --axisymmetric      2D quads in the x-y plane, y the axis (ELFORM 15); without it hex8 solids\n"
    "  --radial-growth G   axisymmetric: ratio of neighbouring radial cells (default 1)\n"
    "  --radius R          axisymmetric: a radial cell boundary at R too (repeatable)\n"
    "  --z0 Z              where the first section starts (along y when axisymmetric)\n"
    "  --gauge Z           a gauge layer at Z (repeatable); --gauge-cut-only keeps its cross section alone\n"
    "  --part PID          the elements' part id (default 1)\n"
    "  --title T           the part's title in the file's comments\n"
    "  --node-offset N, --element-offset E, --set-offset S\n"
    "                      numbering offsets, to put several bodies in one deck\n"
    "  -h, --help          this text; --version its version\n"
    "Exit codes: 0 written, 2 bad arguments or a mesh that cannot be made.\n";

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "-h" || std::string(argv[i]) == "--help") {
      std::cout << kUsage;
      return 0;
    }
    if (std::string(argv[i]) == "--version") {
      std::cout << config::version_line("fe_mesh") << "\n";
      return 0;
    }
  }
  fe::RevolutionMeshOptions opt;
  std::string sections, out, gmsh, abaqus;
  bool axisymmetric = false;
  try {
    config::Args args(argc, argv);
    while (args.next()) {
      if (args.is("--sections")) sections = args.value();
      else if (args.is("--from-gmsh")) gmsh = args.value();
      else if (args.is("--from-abaqus")) abaqus = args.value();
      else if (args.is("--size")) opt.element_size = args.real();
      else if (args.is("--axial-size")) opt.axial_size = args.real();
      else if (args.is("--part")) opt.part = args.integer();
      else if (args.is("--z0")) opt.z0 = args.real();
      else if (args.is("--node-offset")) opt.node_offset = args.integer();
      else if (args.is("--element-offset")) opt.element_offset = args.integer();
      else if (args.is("--set-offset")) opt.set_offset = args.integer();
      else if (args.is("--title")) opt.title = args.value();
      else if (args.is("--gauge")) opt.gauges.push_back(args.real());
      else if (args.is("--axisymmetric")) axisymmetric = true;
      else if (args.is("--radial-growth")) opt.radial_growth = args.real(1.0, 10.0);
      else if (args.is("--gauge-cut-only")) opt.gauge_cut_only = true;
      else if (args.is("--radius")) opt.radii.push_back(args.real());
      else if (args.is("-o")) out = args.value();
      else args.unknown();
    }
    if (!gmsh.empty() || !abaqus.empty()) {
      if (out.empty() || !sections.empty() || (!gmsh.empty() && !abaqus.empty()))
        throw std::invalid_argument("--from-gmsh or --from-abaqus takes -o and no --sections");
      const fe::GmshDeck deck =
          gmsh.empty() ? fe::abaqus_to_keywords(config::read_text_file(abaqus, "Abaqus input"), abaqus)
                       : fe::gmsh_to_keywords(config::read_text_file(gmsh, "gmsh mesh"), gmsh);
      std::ofstream f(out);
      f << deck.keyword_text;
      if (!f) throw std::runtime_error("cannot write " + out);
      std::cout << "fe_mesh: " << deck.nodes << " nodes, " << deck.tetrahedra << " tetrahedra, " << deck.hexahedra
                << " hexahedra, " << deck.prisms << " prisms, " << deck.segments << " segments -> " << out << "\n"
                << deck.summary;
      return 0;
    }
    if (sections.empty() || out.empty()) throw std::invalid_argument("--sections and -o are required");
    const auto table = fe::parse_sections(sections);
    fe::RevolutionMesh mesh = axisymmetric ? fe::mesh_axisymmetric(table, opt) : fe::mesh_revolution(table, opt);
    std::ofstream f(out);
    f << mesh.keyword_text;
    if (!f) throw std::runtime_error("cannot write " + out);
    std::cout << "fe_mesh: " << mesh.nodes << " nodes, " << mesh.elements << " elements -> " << out << "\n";
    for (const auto& face : mesh.faces)
      std::cout << "  set " << face.id << ": " << (axisymmetric ? "y" : "z") << " = " << face.z << " facing "
                << (face.direction < 0 ? "-" : "+") << (axisymmetric ? "y" : "z")
                << ", r " << face.r_in << " to " << face.r_out << "\n";
  } catch (const std::exception& e) {
    std::cerr << "fe_mesh: " << e.what() << "\n(fe_mesh --help lists the options)\n";
    return 2;
  }
  return 0;
}
