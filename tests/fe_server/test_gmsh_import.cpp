// gmsh meshes as keyword meshes (input/mesh_import.hpp). The tool-like
// hollow cylinder tests/fe_server/gmsh/tool.geo is meshed by gmsh 4.8.4
// (Debian's) into tool.msh, committed; CTest's gmsh.tool_meshes_and_runs
// meshes it afresh where gmsh is installed. Each check is one the mesh
// cannot pass by construction: the faces' orientation against the
// geometry, the impulse of a cavity pressure on the bore through the
// co-simulation's load hook, and the refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "config/keyword_reader.hpp"
#include "config/port_table.hpp"
#include "input/deck_reader.hpp"
#include "input/mesh_import.hpp"
#include "loads/cavity_load.hpp"
#include "model/model.hpp"
#include "solver/solver.hpp"

namespace {

const std::string kTool = std::string(PCS_SOURCE_DIR) + "/tests/fe_server/gmsh/tool.msh";
// The same gmsh mesh written as an Abaqus input (gmsh -3 tool.geo -format inp).
const std::string kToolInp = std::string(PCS_SOURCE_DIR) + "/tests/fe_server/gmsh/tool.inp";

std::string import_error(const std::string& text) {
  try {
    fe::gmsh_to_keywords(text, "m.msh");
  } catch (const config::InputError& e) {
    return e.what();
  }
  return "";
}

// One tetrahedron (nodes 1-4) and its bottom face as a physical surface,
// in format 4.1 and 2.2.
const char* kTet41 =
    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 5 \"base\"\n3 7 \"block\"\n$EndPhysicalNames\n"
    "$Entities\n0 0 1 1\n1 0 0 0 1 1 0 1 5 0\n1 0 0 0 1 1 1 1 7 1 1\n$EndEntities\n"
    "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
    "$Elements\n2 2 1 2\n2 1 2 1\n1 1 2 3\n3 1 4 1\n2 1 2 3 4\n$EndElements\n";
const char* kTet22 =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 5 \"base\"\n3 7 \"block\"\n$EndPhysicalNames\n"
    "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
    "$Elements\n2\n1 2 2 5 1 1 2 3\n2 4 2 7 1 1 2 3 4\n$EndElements\n";

}  // namespace

// Both formats give the same deck: the part, its ELFORM 10 section and the
// base's segment turned to face out of the tetrahedron (−z; gmsh wrote it
// 1-2-3, +z).
TEST(GmshImport, BothFormatsGiveTheSameDeckAndFacesPointOut) {
  const fe::GmshDeck a = fe::gmsh_to_keywords(kTet41, "a.msh"), b = fe::gmsh_to_keywords(kTet22, "b.msh");
  EXPECT_EQ(a.keyword_text.substr(a.keyword_text.find("*NODE")), b.keyword_text.substr(b.keyword_text.find("*NODE")));
  EXPECT_EQ(a.tetrahedra, 1u);
  const fe::Model m = fe::parse_deck("*KEYWORD\n" + a.keyword_text + "*MAT_ELASTIC\n7,7850,2e11,0.3\n*END\n", "t.k");
  ASSERT_EQ(m.solids.size(), 1u);
  EXPECT_TRUE(m.solids[0].tet4);
  EXPECT_EQ(m.parts.at(7).title, "block");
  ASSERT_EQ(m.segment_sets.at(5).size(), 1u);
  EXPECT_LT(fe::segment_area_vector(m.segment_sets.at(5)[0], m.x0).z(), 0.0) << "out of the element";
  EXPECT_EQ(m.node_sets.at(5).size(), 3u);
}

// The tool: a tube, outer radius 20 mm, bore 8 mm, 100 mm long. Every
// segment of "top" faces +z, of "bottom" −z, of "bore" the axis; the
// faceted rings' areas are those of inscribed polygons (below π(R² − r²),
// above the 16- and 6-gons the 8 mm size allows at least).
TEST(GmshImport, TheToolsSurfacesFaceOutOfTheTube) {
  const fe::GmshDeck d = fe::gmsh_to_keywords(config::read_text_file(kTool, "mesh"), kTool);
  const fe::Model m = fe::parse_deck("*KEYWORD\n" + d.keyword_text + "*MAT_ELASTIC\n1,7850,2e11,0.3\n*END\n", "tool.k");
  EXPECT_GT(m.solids.size(), 500u);
  double top = 0.0, bottom = 0.0;
  for (const auto& s : m.segment_sets.at(11)) {
    const fe::Vec3 a = fe::segment_area_vector(s, m.x0);
    EXPECT_GT(a.z(), 0.999 * a.norm());
    top += a.norm();
  }
  for (const auto& s : m.segment_sets.at(12)) {
    const fe::Vec3 a = fe::segment_area_vector(s, m.x0);
    EXPECT_LT(a.z(), -0.999 * a.norm());
    bottom += a.norm();
  }
  for (const auto& s : m.segment_sets.at(13)) {
    const fe::Vec3 a = fe::segment_area_vector(s, m.x0), c = m.x0[static_cast<size_t>(s.n[0])];
    EXPECT_LT(a.x() * c.x() + a.y() * c.y(), 0.0) << "towards the axis";
  }
  // The top's triangles tile the annulus between its two polygons (its
  // outer and inner boundary nodes, sorted by angle: shoelace), exactly.
  const double ring = M_PI * (0.02 * 0.02 - 0.008 * 0.008);
  std::vector<std::pair<double, fe::Vec3>> outer, inner;
  for (int id : m.node_sets.at(11)) {
    const fe::Vec3 x = m.x0[static_cast<size_t>(m.node_index.at(id))];
    const double r = std::hypot(x.x(), x.y());
    if (std::fabs(r - 0.02) < 1e-9) outer.push_back({std::atan2(x.y(), x.x()), x});
    if (std::fabs(r - 0.008) < 1e-9) inner.push_back({std::atan2(x.y(), x.x()), x});
  }
  auto polygon = [](std::vector<std::pair<double, fe::Vec3>> v) {
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    double a = 0.0;
    for (size_t k = 0; k < v.size(); ++k) {
      const fe::Vec3 &p = v[k].second, &q = v[(k + 1) % v.size()].second;
      a += 0.5 * (p.x() * q.y() - q.x() * p.y());
    }
    return a;
  };
  ASSERT_GE(outer.size(), 6u);
  ASSERT_GE(inner.size(), 3u);
  EXPECT_NEAR(top, polygon(outer) - polygon(inner), 1e-12 * ring);
  EXPECT_LT(top, ring);
  EXPECT_NEAR(top, bottom, 1e-3 * ring) << "the same rings at both ends";
}

// Pressure in the bore and on the top face through the co-simulation's
// hook (one port wets both): the structure's impulse is −p·ΣA·t, ΣA the
// sets' area vectors (the bore's nearly cancel, the top's is +z·A_top),
// exactly by Newton for a free body; the bore's wall moves out (its ring
// breathes about the static expansion, never inwards of where it began).
TEST(GmshImport, APressureInTheBorePushesTheWallOutWithItsImpulse) {
  const fe::GmshDeck d = fe::gmsh_to_keywords(config::read_text_file(kTool, "mesh"), kTool);
  const fe::Model m = fe::parse_deck("*KEYWORD\n" + d.keyword_text +
                                         "*MAT_ELASTIC\n1,7850,2e11,0.3\n*USER_LOADING_SET\n13,PRESSS,1\n11,PRESSS,1\n*END\n",
                                     "tool.k");
  const auto table = config::parse_port_table(
      "$FMU_SETTINGS\nmodel, tool\ntimestep, 1e-5\n$FMU_HOPSAN_PORTS\n1, bore, Hydraulic\n"
      "$FMU_HOPSAN_SEND\n1, p\n$FMU_HOPSAN_RECEIVE\n1, q\n",
      "tool.cfg");
  fe::CavityPressureLoad load(m, table);
  fe::Solver s(m, 0.9 * fe::Solver::stable_dt(m).dt);
  s.set_user_load(&load);
  const double p = 1e7;
  load.set_pressure(0, p);
  fe::Vec3 area = fe::Vec3::Zero(), momentum = fe::Vec3::Zero();
  double abs_area = 0.0;
  for (int set : {11, 13})
    for (const auto& seg : m.segment_sets.at(set)) {
      area += fe::segment_area_vector(seg, m.x0);
      abs_area += fe::segment_area_vector(seg, m.x0).norm();
    }
  double least_growth = 1e300;
  for (int k = 0; k < 200; ++k) {
    s.step();
    double growth = 0.0;  // the bore nodes' mean radial displacement
    for (int id : m.node_sets.at(13)) {
      const size_t i = static_cast<size_t>(m.node_index.at(id));
      const fe::Vec3 u = s.x()[i] - m.x0[i], r = fe::Vec3(m.x0[i].x(), m.x0[i].y(), 0.0).normalized();
      growth += u.dot(r) / static_cast<double>(m.node_sets.at(13).size());
    }
    if (k > 20) least_growth = std::min(least_growth, growth);
  }
  for (size_t i = 0; i < m.x0.size(); ++i) momentum += m.mass[i] * s.v()[i];
  // The force follows the deformed faces (µm here): 1e-3 of p·Σ|A|·t bounds that.
  EXPECT_LT((momentum + p * area * s.time()).norm(), 1e-3 * p * abs_area * s.time());
  EXPECT_GT(area.z(), 0.9 * M_PI * (0.02 * 0.02 - 0.008 * 0.008)) << "the top's area vector dominates";
  EXPECT_GT(least_growth, 0.0) << "the bore grows";
  EXPECT_LT(std::fabs(s.energies().balance_error), 1e-3 * s.energies().external_work);
}

// What the importer refuses names its line.
TEST(GmshImport, RefusalsNameTheLine) {
  std::string binary = kTet41;
  binary.replace(binary.find("4.1 0 8"), 7, "4.1 1 8");
  EXPECT_NE(import_error(binary).find("m.msh:2: a binary .msh"), std::string::npos) << import_error(binary);
  std::string tet10 = kTet22;
  tet10.replace(tet10.find("2 4 2 7 1 1 2 3 4"), 17, "2 11 2 7 1 1 2 3 4 1 2 3 4 1 2");
  EXPECT_NE(import_error(tet10).find("m.msh:19: a 10-node tetrahedron: fe_mesh reads 4-node tetrahedra"), std::string::npos)
      << import_error(tet10);
  std::string stray = kTet22;
  stray.replace(stray.find("1 2 2 5 1 1 2 3"), 15, "1 3 2 5 1 1 2 3 4");  // a quadrangle on a tetrahedron
  EXPECT_NE(import_error(stray).find("m.msh:18: surface 5 ('base'): face 1 is no face"), std::string::npos)
      << import_error(stray);
  std::string missing = kTet22;
  missing.replace(missing.find("4 0 0 1\n"), 8, "");
  missing.replace(missing.find("$Nodes\n4\n"), 9, "$Nodes\n3\n");
  EXPECT_NE(import_error(missing).find("m.msh:18: element 2: node 4 is not defined"), std::string::npos) << import_error(missing);
  EXPECT_NE(import_error("$Nodes\n").find("m.msh:1: a gmsh mesh begins with $MeshFormat"), std::string::npos);
}

// The tool's mesh through both front ends: gmsh's .msh and the Abaqus input
// gmsh wrote of the same mesh must give the same nodes, the same
// tetrahedra and, set by set (matched by name), the same segments facing
// the same way.
TEST(AbaqusImport, TheSameMeshAsAnAbaqusInputReadsAsItsGmshTwin) {
  const auto material = "*MAT_ELASTIC\n1,7850,2e11,0.3\n*END\n";
  const fe::Model a = fe::parse_deck(
      "*KEYWORD\n" + fe::gmsh_to_keywords(config::read_text_file(kTool, "mesh"), kTool).keyword_text + material, "a.k");
  const fe::Model b = fe::parse_deck(
      "*KEYWORD\n" + fe::abaqus_to_keywords(config::read_text_file(kToolInp, "mesh"), kToolInp).keyword_text + material,
      "b.k");
  ASSERT_EQ(a.node_ids.size(), b.node_ids.size());
  for (size_t i = 0; i < a.node_ids.size(); ++i) {
    const size_t j = static_cast<size_t>(b.node_index.at(a.node_ids[i]));
    EXPECT_LT((a.x0[i] - b.x0[j]).norm(), 1e-12) << "node " << a.node_ids[i];
  }
  ASSERT_EQ(a.solids.size(), b.solids.size());
  std::set<std::array<int, 8>> ea, eb;
  for (const auto& e : a.solids) {
    std::array<int, 8> n;
    for (int k = 0; k < 8; ++k) n[static_cast<size_t>(k)] = a.node_ids[static_cast<size_t>(e.n[k])];
    ea.insert(n);
  }
  for (const auto& e : b.solids) {
    std::array<int, 8> n;
    for (int k = 0; k < 8; ++k) n[static_cast<size_t>(k)] = b.node_ids[static_cast<size_t>(e.n[k])];
    eb.insert(n);
  }
  EXPECT_TRUE(ea == eb) << "the same tetrahedra, node for node";
  // Segment sets by title: 11/12/13 from gmsh's physical tags, 1/2/3 from the input's order.
  for (const auto& [ta, tb] : {std::pair<int, int>{11, 1}, {12, 2}, {13, 3}}) {
    const auto &sa = a.segment_sets.at(ta), &sb = b.segment_sets.at(tb);
    ASSERT_EQ(sa.size(), sb.size()) << ta;
    fe::Vec3 va = fe::Vec3::Zero(), vb = fe::Vec3::Zero();
    double aa = 0.0, ab = 0.0;
    for (const auto& seg : sa) va += fe::segment_area_vector(seg, a.x0), aa += fe::segment_area_vector(seg, a.x0).norm();
    for (const auto& seg : sb) vb += fe::segment_area_vector(seg, b.x0), ab += fe::segment_area_vector(seg, b.x0).norm();
    EXPECT_NEAR(aa, ab, 1e-12 * aa) << ta;
    EXPECT_LT((va - vb).norm(), 1e-12 * aa) << ta << ": the same way out";
  }
}

// A hexahedron in an Abaqus input: *SOLID SECTION names the part, a
// *SURFACE of all six faces S1-S6 faces out of it (the faces close: their
// area vectors sum to 0, each points away from the centre), an element set
// by GENERATE, a data line continued after a trailing comma; what is not a
// mesh is listed as not converted; what it refuses names the line.
TEST(AbaqusImport, FacesByNumberFaceOutAndRefusalsNameTheLine) {
  const std::string inp =
      "*HEADING\ncube\n*NODE\n1,0,0,0\n2,1,0,0\n3,1,1,0\n4,0,1,0\n5,0,0,1\n6,1,0,1\n7,1,1,1\n8,0,1,1\n"
      "*ELEMENT, TYPE=C3D8R\n7, 1, 2, 3, 4,\n5, 6, 7, 8\n*ELSET, ELSET=block, GENERATE\n7, 7, 1\n"
      "*SOLID SECTION, ELSET=block, MATERIAL=steel\n*SURFACE, NAME=skin\nblock, S1\nblock, S2\nblock, S3\n"
      "7, S4\n7, S5\n7, S6\n*MATERIAL, NAME=steel\n*ELASTIC\n2e11, 0.3\n";
  const fe::GmshDeck d = fe::abaqus_to_keywords(inp, "c.inp");
  EXPECT_NE(d.summary.find("part 1 'block': 1 hexahedra"), std::string::npos) << d.summary;
  EXPECT_NE(d.summary.find("not converted (fe_mesh takes the mesh only): *ELASTIC *MATERIAL"), std::string::npos) << d.summary;
  const fe::Model m = fe::parse_deck("*KEYWORD\n" + d.keyword_text + "*MAT_ELASTIC\n1,7850,2e11,0.3\n*END\n", "c.k");
  const auto& skin = m.segment_sets.at(1);
  ASSERT_EQ(skin.size(), 6u);
  fe::Vec3 sum = fe::Vec3::Zero();
  for (const auto& seg : skin) {
    const fe::Vec3 a = fe::segment_area_vector(seg, m.x0);
    fe::Vec3 c = fe::Vec3::Zero();
    for (int k = 0; k < 4; ++k) c += 0.25 * m.x0[static_cast<size_t>(seg.n[k])];
    EXPECT_GT(a.dot(c - fe::Vec3(0.5, 0.5, 0.5)), 0.0) << "out of the cube";
    EXPECT_NEAR(a.norm(), 1.0, 1e-12);
    sum += a;
  }
  EXPECT_LT(sum.norm(), 1e-12);
  auto error = [](const std::string& text) {
    try {
      fe::abaqus_to_keywords(text, "e.inp");
    } catch (const config::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("*NODE\n1,0,0,0\n*ELEMENT, TYPE=C3D10\n").find("e.inp:3: element type C3D10"), std::string::npos);
  EXPECT_NE(error("*PART, NAME=p\n").find("e.inp:1: *PART: an input of parts and an assembly"), std::string::npos);
  EXPECT_NE(error(inp + "*SURFACE, NAME=s2\nnowhere, S1\n").find("e.inp:29: element set nowhere is not defined"),
            std::string::npos)
      << error(inp + "*SURFACE, NAME=s2\nnowhere, S1\n");
  EXPECT_NE(error("*NODE\n1,0,0,0\n*ELEMENT, TYPE=C3D4\n1, 1, 1, 1\n").find("e.inp:4: element 1: 3 nodes where C3D4 has 4"),
            std::string::npos);
}
