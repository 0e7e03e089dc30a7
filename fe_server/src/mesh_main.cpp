// fe_mesh: bodies of revolution → keyword mesh (nodes, hex8 elements, face sets).
//
//   fe_mesh --sections "L,ro[,ri]; L,ro[,ri]; ..." [--size h] [--part PID] [--z0 Z]
//           [--node-offset N] [--element-offset E] [--set-offset S] [--title T]
//           [--gauge Z ...] -o mesh.k
// Include the result from a deck (*INCLUDE) that defines the part's *PART,
// *SECTION_SOLID and material.
#include <fstream>
#include <iostream>

#include "mesher.hpp"

int main(int argc, char** argv) {
  fe::RevolutionMeshOptions opt;
  std::string sections, out;
  try {
    for (int i = 1; i < argc; ++i) {
      std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
        return argv[++i];
      };
      if (a == "--sections") sections = value();
      else if (a == "--size") opt.element_size = std::stod(value());
      else if (a == "--axial-size") opt.axial_size = std::stod(value());
      else if (a == "--part") opt.part = std::stoi(value());
      else if (a == "--z0") opt.z0 = std::stod(value());
      else if (a == "--node-offset") opt.node_offset = std::stoi(value());
      else if (a == "--element-offset") opt.element_offset = std::stoi(value());
      else if (a == "--set-offset") opt.set_offset = std::stoi(value());
      else if (a == "--title") opt.title = value();
      else if (a == "--gauge") opt.gauges.push_back(std::stod(value()));
      else if (a == "-o") out = value();
      else throw std::invalid_argument("unknown argument " + a);
    }
    if (sections.empty() || out.empty()) throw std::invalid_argument("--sections and -o are required");
    fe::RevolutionMesh mesh = fe::mesh_revolution(fe::parse_sections(sections), opt);
    std::ofstream f(out);
    f << mesh.keyword_text;
    if (!f) throw std::runtime_error("cannot write " + out);
    std::cout << "fe_mesh: " << mesh.nodes << " nodes, " << mesh.elements << " elements -> " << out << "\n";
    for (const auto& face : mesh.faces)
      std::cout << "  set " << face.id << ": z = " << face.z << " facing " << (face.direction < 0 ? "-z" : "+z")
                << ", r " << face.r_in << " to " << face.r_out << "\n";
  } catch (const std::exception& e) {
    std::cerr << "fe_mesh: " << e.what() << "\n"
              << "usage: fe_mesh --sections \"L,ro[,ri]; ...\" [--size h] [--part PID] [--z0 Z] -o mesh.k\n";
    return 2;
  }
  return 0;
}
