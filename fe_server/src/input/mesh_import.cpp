#include "input/mesh_import.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "config/keyword_reader.hpp"

namespace fe {

namespace {

using config::InputError;
using config::SourceLocation;

// A field as an integer or a finite number, else an error at `at`.
long integer_at(const std::string& f, const char* what, const SourceLocation& at) {
  char* end = nullptr;
  const long v = std::strtol(f.c_str(), &end, 10);
  if (f.empty() || end == f.c_str() || *end) throw InputError(at, std::string(what) + " '" + f + "' is not an integer");
  return v;
}
double real_at(const std::string& f, const char* what, const SourceLocation& at) {
  char* end = nullptr;
  const double v = std::strtod(f.c_str(), &end);
  if (f.empty() || end == f.c_str() || *end || !std::isfinite(v))
    throw InputError(at, std::string(what) + " '" + f + "' is not a finite number");
  return v;
}

// The file as numbered lines of whitespace-separated tokens.
class Lines {
 public:
  Lines(const std::string& text, const std::string& name) : name_(name) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines_.push_back(line);
    }
  }
  bool done() const { return at_ >= lines_.size(); }
  // The next line's tokens; fails at the end of the file.
  std::vector<std::string> next(const char* expected) {
    if (done()) throw InputError(where(), std::string("the file ends where ") + expected + " was expected");
    std::istringstream in(lines_[at_++]);
    std::vector<std::string> t;
    std::string s;
    while (in >> s) t.push_back(s);
    return t;
  }
  const std::string& raw() const { return lines_[at_ - 1]; }
  SourceLocation where() const { return {name_, static_cast<int>(std::min(at_, lines_.size()))}; }
  [[noreturn]] void fail(const std::string& message) const { throw InputError(where(), message); }
  long integer(const std::vector<std::string>& t, size_t k, const char* what) const {
    if (k >= t.size()) fail(std::string("missing ") + what);
    return integer_at(t[k], what, where());
  }
  double real(const std::vector<std::string>& t, size_t k, const char* what) const {
    if (k >= t.size()) fail(std::string("missing ") + what);
    return real_at(t[k], what, where());
  }

 private:
  std::string name_;
  std::vector<std::string> lines_;
  size_t at_ = 0;
};

struct Element {
  long tag = 0;
  int type = 0;
  int dim = 0, entity = 0, physical = 0;  // physical: 2.2's own tag (4.1: from the entity)
  std::vector<long> nodes;
  int line = 0;
};

// Nodes per gmsh element type that this importer reads, and the dimension.
int node_count(int type) {
  switch (type) {
    case 2: return 3;  // triangle
    case 3: return 4;  // quadrangle
    case 4: return 4;  // tetrahedron
    case 5: return 8;  // hexahedron
    case 6: return 6;  // prism
    default: return 0;
  }
}
// gmsh's element types by dimension: points 15; lines 1, 8, 26-28; faces
// 2, 3, 9, 10, 16, 20-25; anything else is a volume (and, unless it is a
// tetrahedron, hexahedron or prism of first order, refused).
int dimension(int type) {
  if (type == 15) return 0;
  if (type == 1 || type == 8 || (type >= 26 && type <= 28)) return 1;
  if (type == 2 || type == 3 || type == 9 || type == 10 || type == 16 || (type >= 20 && type <= 25)) return 2;
  return 3;
}

// Each volume element's faces, counter-clockwise seen from outside (gmsh's
// node orders; its hexahedra number as LS-DYNA's do).
const std::vector<std::vector<int>>& faces_of(int type) {
  static const std::vector<std::vector<int>> tet = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  static const std::vector<std::vector<int>> hex = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                    {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  static const std::vector<std::vector<int>> prism = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}};
  return type == 4 ? tet : type == 5 ? hex : prism;
}

std::vector<long> sorted(std::vector<long> v) {
  std::sort(v.begin(), v.end());
  return v;
}

std::string element_name(int type) {
  static const std::map<int, std::string> names = {
      {1, "2-node line"},         {8, "3-node line"},      {9, "6-node triangle"}, {10, "9-node quadrangle"},
      {11, "10-node tetrahedron"}, {12, "27-node hexahedron"}, {13, "18-node prism"}, {7, "5-node pyramid"},
      {14, "14-node pyramid"},     {16, "8-node quadrangle"}, {17, "20-node hexahedron"}, {18, "15-node prism"}};
  const auto it = names.find(type);
  return it == names.end() ? "element type " + std::to_string(type) : it->second;
}

struct Mesh {
  std::map<long, std::array<double, 3>> nodes;
  std::vector<Element> elements;
  std::map<std::pair<int, int>, std::string> physical_names;       // (dim, tag) → name
  std::map<std::pair<int, int>, std::vector<int>> entity_physicals;  // (dim, entity) → physical tags
  double version = 0.0;
};

void read_section(Lines& in, const std::string& head, Mesh& mesh) {
  auto expect_end = [&](const std::string& end) {
    const auto t = in.next(end.c_str());
    if (t.empty() || t[0] != end) in.fail("expected " + end + " here");
  };
  if (head == "$MeshFormat") {
    const auto t = in.next("the format line");
    mesh.version = in.real(t, 0, "the format version");
    if (in.integer(t, 1, "the file type") != 0)
      in.fail("a binary .msh: write it as ASCII (gmsh -save with Mesh.Binary = 0, or -bin 0 omitted)");
    if (mesh.version != 4.1 && mesh.version != 2.2)
      in.fail("format " + t[0] + ": fe_mesh reads gmsh's formats 4.1 and 2.2 (gmsh -format msh41 or msh22)");
    expect_end("$EndMeshFormat");
  } else if (head == "$PhysicalNames") {
    const long n = in.integer(in.next("the count"), 0, "the number of names");
    for (long k = 0; k < n; ++k) {
      const auto t = in.next("a physical name");
      const int dim = static_cast<int>(in.integer(t, 0, "the dimension")), tag = static_cast<int>(in.integer(t, 1, "the tag"));
      const std::string& line = in.raw();
      const size_t a = line.find('"'), b = line.rfind('"');
      mesh.physical_names[{dim, tag}] = a != std::string::npos && b > a ? line.substr(a + 1, b - a - 1) : "";
    }
    expect_end("$EndPhysicalNames");
  } else if (head == "$Entities") {
    const auto counts = in.next("the entity counts");
    for (int dim = 0; dim < 4; ++dim) {
      const long n = in.integer(counts, static_cast<size_t>(dim), "an entity count");
      for (long k = 0; k < n; ++k) {
        const auto t = in.next("an entity");
        const int tag = static_cast<int>(in.integer(t, 0, "the entity tag"));
        const size_t at = dim == 0 ? 4 : 7;  // points: x y z; others: their bounding box
        const long np = in.integer(t, at, "the number of physical tags");
        std::vector<int>& ph = mesh.entity_physicals[{dim, tag}];
        for (long p = 0; p < np; ++p) ph.push_back(static_cast<int>(std::labs(in.integer(t, at + 1 + static_cast<size_t>(p), "a physical tag"))));
      }
    }
    expect_end("$EndEntities");
  } else if (head == "$Nodes" && mesh.version == 4.1) {
    const auto t = in.next("the node counts");
    const long blocks = in.integer(t, 0, "the number of blocks");
    for (long b = 0; b < blocks; ++b) {
      const auto h = in.next("a node block");
      if (in.integer(h, 2, "the parametric flag") != 0) in.fail("parametric nodes: save the mesh without them (Mesh.SaveParametric = 0)");
      const long n = in.integer(h, 3, "the block's node count");
      std::vector<long> tags;
      for (long k = 0; k < n; ++k) tags.push_back(in.integer(in.next("a node tag"), 0, "the node tag"));
      for (long k = 0; k < n; ++k) {
        const auto x = in.next("node coordinates");
        mesh.nodes[tags[static_cast<size_t>(k)]] = {in.real(x, 0, "x"), in.real(x, 1, "y"), in.real(x, 2, "z")};
      }
    }
    expect_end("$EndNodes");
  } else if (head == "$Nodes") {  // 2.2
    const long n = in.integer(in.next("the node count"), 0, "the number of nodes");
    for (long k = 0; k < n; ++k) {
      const auto x = in.next("a node");
      mesh.nodes[in.integer(x, 0, "the node tag")] = {in.real(x, 1, "x"), in.real(x, 2, "y"), in.real(x, 3, "z")};
    }
    expect_end("$EndNodes");
  } else if (head == "$Elements") {
    auto element = [&](const std::vector<std::string>& t, size_t first, Element e) {
      e.line = in.where().line;
      const int count = node_count(e.type);
      e.dim = dimension(e.type);
      if (e.dim >= 2 && count == 0)
        in.fail("a " + element_name(e.type) + ": fe_mesh reads 4-node tetrahedra, 8-node hexahedra, 6-node prisms and "
                "their 3- and 4-node faces (first-order meshes: Mesh.ElementOrder = 1, no pyramids)");
      if (count == 0) return;  // points and lines: nothing to carry over
      for (int k = 0; k < count; ++k) e.nodes.push_back(in.integer(t, first + static_cast<size_t>(k), "a node tag"));
      mesh.elements.push_back(e);
    };
    if (mesh.version == 4.1) {
      const long blocks = in.integer(in.next("the element counts"), 0, "the number of blocks");
      for (long b = 0; b < blocks; ++b) {
        const auto h = in.next("an element block");
        Element proto;
        proto.dim = static_cast<int>(in.integer(h, 0, "the entity dimension"));
        proto.entity = static_cast<int>(in.integer(h, 1, "the entity tag"));
        proto.type = static_cast<int>(in.integer(h, 2, "the element type"));
        const long n = in.integer(h, 3, "the block's element count");
        for (long k = 0; k < n; ++k) {
          const auto t = in.next("an element");
          Element e = proto;
          e.tag = in.integer(t, 0, "the element tag");
          element(t, 1, e);
        }
      }
    } else {
      const long n = in.integer(in.next("the element count"), 0, "the number of elements");
      for (long k = 0; k < n; ++k) {
        const auto t = in.next("an element");
        Element e;
        e.tag = in.integer(t, 0, "the element tag");
        e.type = static_cast<int>(in.integer(t, 1, "the element type"));
        const long tags = in.integer(t, 2, "the number of tags");
        if (tags >= 1) e.physical = static_cast<int>(in.integer(t, 3, "the physical tag"));
        if (tags >= 2) e.entity = static_cast<int>(in.integer(t, 4, "the entity tag"));
        element(t, 3 + static_cast<size_t>(tags), e);
      }
    }
    expect_end("$EndElements");
  } else {  // a section this importer has no use for ($Periodic, $NodeData, ...)
    const std::string end = "$End" + head.substr(1);
    while (true) {
      const auto t = in.next(end.c_str());
      if (!t.empty() && t[0] == end) break;
    }
  }
}

// What the front ends (gmsh's .msh, Abaqus' .inp) hand the writer: each
// volume element's part (0: none) and each face element's surface groups,
// the groups' names, and faces given as a volume element's face (Abaqus'
// *SURFACE, already facing out).
struct Groups {
  std::vector<int> part_of;                  // per element of the mesh
  std::vector<std::vector<int>> surfaces_of;  // per element of the mesh
  std::map<int, std::string> part_names, surface_names;
  struct Face {
    int surface;
    size_t element;
    std::vector<int> corners;  // of the element's nodes, counter-clockwise seen from outside
    int line;
  };
  std::vector<Face> faces;
};

GmshDeck keywords_of(const Mesh& mesh, const Groups& g, const std::string& name, const std::string& origin) {
  // Parts: PID → the kind of its elements (ELFORM 10 or 1) and title.
  struct PartInfo {
    int elform = 0;
    size_t count = 0;
  };
  std::map<int, PartInfo> parts;
  std::vector<std::pair<const Element*, int>> volume;  // element, part
  std::map<std::vector<long>, std::vector<std::pair<size_t, int>>> face_owner;  // sorted nodes → (volume index, face)
  std::map<size_t, size_t> volume_index;  // mesh element → index into `volume`
  std::set<long> used;
  for (size_t k = 0; k < mesh.elements.size(); ++k) {
    const Element& e = mesh.elements[k];
    if (e.dim != 3 || g.part_of[k] == 0) continue;
    const int pid = g.part_of[k];
    PartInfo& p = parts[pid];
    const int elform = e.type == 4 ? 10 : 1;
    if (p.elform && p.elform != elform)
      throw InputError({name, e.line}, "part " + std::to_string(pid) +
                                           " mixes tetrahedra with hexahedra or prisms: one ELFORM per part; put them in two groups");
    p.elform = elform;
    ++p.count;
    for (long n : e.nodes) {
      if (!mesh.nodes.count(n)) throw InputError({name, e.line}, "element " + std::to_string(e.tag) + ": node " + std::to_string(n) + " is not defined");
      used.insert(n);
    }
    const auto& fs = faces_of(e.type);
    for (size_t f = 0; f < fs.size(); ++f) {
      std::vector<long> key;
      for (int c : fs[f]) key.push_back(e.nodes[static_cast<size_t>(c)]);
      face_owner[sorted(key)].push_back({volume.size(), static_cast<int>(f)});
    }
    volume_index[k] = volume.size();
    volume.push_back({&e, pid});
  }
  if (volume.empty()) throw InputError({name, 1}, "the mesh has no volume elements in a part (mesh it in 3D)");

  // Surfaces: group → segments oriented out of their element.
  std::map<int, std::vector<std::vector<long>>> surfaces;
  auto surface_name = [&](int tag) {
    const auto nm = g.surface_names.find(tag);
    return "surface " + std::to_string(tag) + (nm != g.surface_names.end() ? " ('" + nm->second + "')" : std::string());
  };
  for (size_t k = 0; k < mesh.elements.size(); ++k) {
    const Element& e = mesh.elements[k];
    if (e.dim != 2) continue;
    for (int tag : g.surfaces_of[k]) {
      const auto owner = face_owner.find(sorted(e.nodes));
      if (owner == face_owner.end())
        throw InputError({name, e.line}, surface_name(tag) + ": face " + std::to_string(e.tag) +
                                             " is no face of a volume element (is the surface meshed on the volume?)");
      if (owner->second.size() > 1)
        throw InputError({name, e.line}, surface_name(tag) + ": face " + std::to_string(e.tag) +
                                             " lies between two volume elements: an inner face has no outside for a pressure or contact");
      const auto [v, f] = owner->second[0];
      const Element& ve = *volume[v].first;
      std::vector<long> seg;
      for (int c : faces_of(ve.type)[static_cast<size_t>(f)]) seg.push_back(ve.nodes[static_cast<size_t>(c)]);
      surfaces[tag].push_back(seg);
    }
  }
  for (const Groups::Face& f : g.faces) {
    if (!volume_index.count(f.element))
      throw InputError({name, f.line}, surface_name(f.surface) + ": element " + std::to_string(mesh.elements[f.element].tag) +
                                           " is in no part");
    std::vector<long> seg;
    for (int c : f.corners) seg.push_back(mesh.elements[f.element].nodes[static_cast<size_t>(c)]);
    surfaces[f.surface].push_back(seg);
  }

  GmshDeck out;
  std::ostringstream d, s;
  d << "$ fe_mesh " << origin << " " << name << ": " << used.size() << " nodes\n"
    << "$ include it from a deck that defines each part's material (*MAT_... with MID = PID)\n*NODE\n";
  d.precision(17);
  for (long n : used) {
    const auto& x = mesh.nodes.at(n);
    d << n << "," << x[0] << "," << x[1] << "," << x[2] << "\n";
  }
  for (const auto& [pid, p] : parts) {
    const auto nm = g.part_names.find(pid);
    const std::string title = nm != g.part_names.end() && !nm->second.empty() ? nm->second : "volume " + std::to_string(pid);
    d << "*PART\n" << title << "\n" << pid << "," << pid << "," << pid << "\n*SECTION_SOLID\n" << pid << "," << p.elform << "\n";
    s << "  part " << pid << " '" << title << "': " << p.count << (p.elform == 10 ? " tetrahedra" : " hexahedra/prisms")
      << " (ELFORM " << p.elform << ")\n";
  }
  d << "*ELEMENT_SOLID\n";
  for (const auto& [e, pid] : volume) {
    d << e->tag << "," << pid;
    if (e->type == 6) {  // a prism as LS-DYNA's degenerate hexahedron
      const auto& n = e->nodes;
      for (long id : {n[0], n[1], n[2], n[2], n[3], n[4], n[5], n[5]}) d << "," << id;
    } else {
      for (long id : e->nodes) d << "," << id;
    }
    d << "\n";
    (e->type == 4 ? out.tetrahedra : e->type == 5 ? out.hexahedra : out.prisms) += 1;
  }
  for (const auto& [tag, segs] : surfaces) {
    const auto nm = g.surface_names.find(tag);
    const std::string title = nm != g.surface_names.end() ? nm->second : "surface " + std::to_string(tag);
    d << "*SET_SEGMENT_TITLE\n" << title << "\n" << tag << "\n";
    std::set<long> nodes;
    for (const auto& q : segs) {
      d << q[0] << "," << q[1] << "," << q[2] << "," << (q.size() == 4 ? q[3] : q[2]) << "\n";
      nodes.insert(q.begin(), q.end());
    }
    d << "*SET_NODE_LIST_TITLE\n" << title << "\n" << tag << "\n";
    size_t k = 0;
    for (long n : nodes) d << n << (++k % 8 == 0 || k == nodes.size() ? "\n" : ",");
    s << "  surface " << tag << " '" << title << "': " << segs.size() << " segments (segment set " << tag << "), "
      << nodes.size() << " nodes (node set " << tag << ")\n";
    out.segments += segs.size();
  }
  out.keyword_text = d.str();
  out.nodes = used.size();
  out.summary = s.str();
  return out;
}

}  // namespace

namespace {

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}
std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}
// A data line's comma-separated fields (a trailing comma leaves no field).
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> f;
  std::string cur;
  std::istringstream in(line);
  while (std::getline(in, cur, ',')) f.push_back(trim(cur));
  while (!f.empty() && f.back().empty()) f.pop_back();
  return f;
}

// Abaqus' element types this reader takes, as gmsh's type codes.
int abaqus_type(const std::string& t) {
  static const std::map<std::string, int> types = {
      {"C3D4", 4},  {"C3D8", 5},  {"C3D8R", 5}, {"C3D8I", 5}, {"C3D6", 6},  {"CPS3", 2},  {"CPE3", 2},
      {"S3", 2},    {"S3R", 2},   {"M3D3", 2},  {"STRI3", 2}, {"R3D3", 2},  {"SFM3D3", 2}, {"CPS4", 3},
      {"CPE4", 3},  {"S4", 3},    {"S4R", 3},   {"M3D4", 3},  {"M3D4R", 3}, {"R3D4", 3},  {"SFM3D4", 3}};
  const auto it = types.find(upper(t));
  return it == types.end() ? 0 : it->second;
}

// Abaqus' faces S1.. of its solids as sets of the element's corners (from 0).
const std::vector<std::vector<int>>& abaqus_faces(int type) {
  static const std::vector<std::vector<int>> tet = {{0, 1, 2}, {0, 1, 3}, {1, 2, 3}, {0, 2, 3}};
  static const std::vector<std::vector<int>> hex = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 4, 5},
                                                    {1, 2, 5, 6}, {2, 3, 6, 7}, {0, 3, 4, 7}};
  static const std::vector<std::vector<int>> prism = {{0, 1, 2}, {3, 4, 5}, {0, 1, 3, 4}, {1, 2, 4, 5}, {0, 2, 3, 5}};
  return type == 4 ? tet : type == 5 ? hex : prism;
}

}  // namespace

GmshDeck abaqus_to_keywords(const std::string& text, const std::string& name) {
  Mesh mesh;
  std::map<long, size_t> element_index;             // element id → index in mesh.elements
  std::vector<std::pair<std::string, std::vector<long>>> elsets;  // in order of definition
  std::map<std::string, size_t> elset_index;
  std::set<std::string> line_elsets;                // elsets named on *ELEMENT lines
  std::vector<std::pair<std::string, int>> sections;  // *SOLID SECTION elsets, with their lines
  struct SurfaceLine {
    std::string surface, target, face;
    int line;
  };
  std::vector<SurfaceLine> surface_lines;
  std::vector<std::string> surface_order;
  std::map<std::string, size_t> ignored;  // keywords not converted → count
  std::istringstream in(text);
  std::string raw, keyword;
  std::map<std::string, std::string> options;
  int line = 0;
  int type = 0;
  std::vector<std::string> pending;  // an element's fields across continued lines
  int pending_line = 0;
  auto elset = [&](const std::string& n) -> std::vector<long>& {
    const std::string key = upper(n);
    if (!elset_index.count(key)) {
      elset_index[key] = elsets.size();
      elsets.push_back({n, {}});
    }
    return elsets[elset_index[key]].second;
  };
  auto fail = [&](const std::string& m) { throw InputError({name, line}, m); };
  auto integer = [&](const std::string& f, const char* what) { return integer_at(f, what, {name, line}); };
  auto real = [&](const std::string& f, const char* what) { return real_at(f, what, {name, line}); };
  while (std::getline(in, raw)) {
    ++line;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    const std::string t = trim(raw);
    if (t.empty() || t.rfind("**", 0) == 0) continue;
    if (t[0] == '*') {
      if (!pending.empty()) fail("element " + pending[0] + " (line " + std::to_string(pending_line) + ") lacks nodes");
      const auto f = fields(t);
      keyword = upper(f[0]);
      options.clear();
      for (size_t k = 1; k < f.size(); ++k) {
        const size_t eq = f[k].find('=');
        options[upper(trim(f[k].substr(0, eq)))] = eq == std::string::npos ? "" : trim(f[k].substr(eq + 1));
      }
      if (keyword == "*PART" || keyword == "*INSTANCE" || keyword == "*ASSEMBLY")
        fail(keyword + ": an input of parts and an assembly; write it flattened (Abaqus/CAE: without parts and "
                       "assembly) or mesh with gmsh");
      if (keyword == "*ELEMENT") {
        type = abaqus_type(options["TYPE"]);
        if (type == 0)
          fail("element type " + options["TYPE"] + ": fe_mesh reads C3D4, C3D8(R, I), C3D6 and 3- and 4-node faces "
               "(first order; C3D10 and C3D20 are second order)");
        if (options.count("ELSET")) line_elsets.insert(upper(options["ELSET"])), elset(options["ELSET"]);
      } else if (keyword == "*SOLID SECTION") {
        if (!options.count("ELSET")) fail("*SOLID SECTION without ELSET");
        sections.push_back({options["ELSET"], line});
      } else if (keyword == "*SURFACE") {
        if (options.count("TYPE") && upper(options["TYPE"]) != "ELEMENT") fail("*SURFACE, TYPE=" + options["TYPE"] + ": only element-face surfaces are read");
        if (!options.count("NAME")) fail("*SURFACE without NAME");
        surface_order.push_back(options["NAME"]);
      } else if (keyword != "*NODE" && keyword != "*ELSET" && keyword != "*HEADING") {
        ++ignored[keyword];
      }
      continue;
    }
    if (keyword == "*NODE") {
      const auto f = fields(t);
      if (f.size() < 3) fail("a node needs its id and coordinates");
      mesh.nodes[integer(f[0], "the node id")] = {real(f[1], "x"), real(f[2], "y"), f.size() > 3 ? real(f[3], "z") : 0.0};
    } else if (keyword == "*ELEMENT") {
      const bool more = t.back() == ',';
      if (pending.empty()) pending_line = line;
      for (const auto& f : fields(t)) pending.push_back(f);
      const size_t need = static_cast<size_t>(node_count(type)) + 1;
      if (pending.size() < need && more) continue;
      if (pending.size() != need)
        throw InputError({name, pending_line}, "element " + pending[0] + ": " + std::to_string(pending.size() - 1) +
                                                   " nodes where " + options["TYPE"] + " has " + std::to_string(need - 1));
      Element e;
      e.tag = integer(pending[0], "the element id");
      e.type = type;
      e.dim = dimension(type);
      e.line = pending_line;
      for (size_t k = 1; k < need; ++k) e.nodes.push_back(integer(pending[k], "a node id"));
      if (element_index.count(e.tag)) throw InputError({name, pending_line}, "element " + pending[0] + " defined twice");
      element_index[e.tag] = mesh.elements.size();
      mesh.elements.push_back(e);
      if (options.count("ELSET")) elset(options["ELSET"]).push_back(e.tag);
      pending.clear();
    } else if (keyword == "*ELSET") {
      if (!options.count("ELSET")) fail("*ELSET without ELSET=");
      auto& set = elset(options["ELSET"]);
      const auto f = fields(t);
      if (options.count("GENERATE")) {
        if (f.size() < 2) fail("GENERATE needs first, last[, step]");
        const long a = integer(f[0], "first"), b = integer(f[1], "last"), step = f.size() > 2 ? integer(f[2], "step") : 1;
        if (step <= 0 || b < a) fail("GENERATE " + t + ": an empty or endless range");
        for (long id = a; id <= b; id += step) set.push_back(id);
      } else {
        for (const auto& x : f) {
          if (!x.empty() && (std::isdigit(static_cast<unsigned char>(x[0])) || x[0] == '-')) set.push_back(integer(x, "an element id"));
          else if (elset_index.count(upper(x))) {
            const auto other = elsets[elset_index[upper(x)]].second;
            set.insert(set.end(), other.begin(), other.end());
          } else fail("element set " + x + " is not defined above");
        }
      }
    } else if (keyword == "*SURFACE") {
      const auto f = fields(t);
      if (f.size() != 2) fail("a surface line is an element set (or element) and a face, S1 to S6");
      surface_lines.push_back({surface_order.back(), f[0], upper(f[1]), line});
    }
  }
  if (!pending.empty()) throw InputError({name, pending_line}, "element " + pending[0] + " lacks nodes");

  Groups g;
  g.part_of.assign(mesh.elements.size(), 0);
  g.surfaces_of.resize(mesh.elements.size());
  auto members = [&](const std::string& set, int at) -> const std::vector<long>& {
    const auto it = elset_index.find(upper(set));
    if (it == elset_index.end()) throw InputError({name, at}, "element set " + set + " is not defined");
    return elsets[it->second].second;
  };
  auto index_of = [&](long id, int at) {
    const auto it = element_index.find(id);
    if (it == element_index.end()) throw InputError({name, at}, "element " + std::to_string(id) + " is not defined");
    return it->second;
  };
  // Parts: the solid sections' element sets; else the element sets of
  // volume elements written as *ELSET (gmsh's physical volumes); else
  // those named on *ELEMENT lines.
  std::vector<std::pair<std::string, int>> part_sets = sections;
  auto volume_only = [&](const std::vector<long>& ids) {
    for (long id : ids)
      if (!element_index.count(id) || mesh.elements[element_index[id]].dim != 3) return false;
    return !ids.empty();
  };
  if (part_sets.empty())
    for (const bool listed : {true, false}) {  // listed: written as *ELSET
      for (const auto& [n, ids] : elsets)
        if ((line_elsets.count(upper(n)) == 0) == listed && volume_only(ids)) part_sets.push_back({n, 0});
      if (!part_sets.empty()) break;
    }
  int pid = 0;
  for (const auto& [set, at] : part_sets) {
    g.part_names[++pid] = set;
    for (long id : members(set, at)) {
      const size_t k = index_of(id, at);
      if (mesh.elements[k].dim != 3) continue;
      if (g.part_of[k] != 0)
        throw InputError({name, mesh.elements[k].line}, "element " + std::to_string(id) + " is in two parts (" +
                                                            g.part_names[g.part_of[k]] + " and " + set + ")");
      g.part_of[k] = pid;
    }
  }
  // Surfaces: *SURFACE's faces, and element sets of face elements.
  int sid = 0;
  std::map<std::string, int> surface_tag;
  for (const std::string& n : surface_order) surface_tag[upper(n)] = ++sid, g.surface_names[sid] = n;
  for (const SurfaceLine& sl : surface_lines) {
    if (sl.face.size() < 2 || sl.face[0] != 'S') throw InputError({name, sl.line}, "face " + sl.face + ": S1 to S6");
    const int face = std::atoi(sl.face.c_str() + 1) - 1;
    std::vector<long> ids;
    if (std::isdigit(static_cast<unsigned char>(sl.target[0]))) ids.push_back(std::atol(sl.target.c_str()));
    else ids = members(sl.target, sl.line);
    for (long id : ids) {
      const size_t k = index_of(id, sl.line);
      const Element& e = mesh.elements[k];
      if (e.dim != 3) throw InputError({name, sl.line}, "element " + std::to_string(id) + " is no solid: its faces S1.. are not solid faces");
      const auto& faces = abaqus_faces(e.type);
      if (face < 0 || face >= static_cast<int>(faces.size()))
        throw InputError({name, sl.line}, "face " + sl.face + " of element " + std::to_string(id) + ": it has S1 to S" + std::to_string(faces.size()));
      // The same corners in the outward order of faces_of.
      std::vector<int> want = faces[static_cast<size_t>(face)];
      for (const auto& f : faces_of(e.type)) {
        std::vector<int> have = f;
        std::sort(have.begin(), have.end());
        if (have == want) g.faces.push_back({surface_tag[upper(sl.surface)], k, f, sl.line});
      }
    }
  }
  // (As for parts: the *ELSETs of faces if there are any, else the sets
  // named on *ELEMENT lines; gmsh writes both for one physical surface.)
  auto faces_only = [&](const std::vector<long>& ids) {
    for (long id : ids)
      if (!element_index.count(id) || mesh.elements[element_index[id]].dim != 2) return false;
    return !ids.empty();
  };
  for (const bool listed : {true, false}) {
    bool any = false;
    for (const auto& [n, ids] : elsets) {
      if ((line_elsets.count(upper(n)) == 0) != listed || !faces_only(ids)) continue;
      any = true;
      g.surface_names[++sid] = n;
      for (long id : ids) g.surfaces_of[element_index[id]].push_back(sid);
    }
    if (any) break;
  }
  GmshDeck deck = keywords_of(mesh, g, name, "--from-abaqus");
  if (!ignored.empty()) {
    deck.summary += "  not converted (fe_mesh takes the mesh only):";
    for (const auto& [k, n] : ignored) deck.summary += " " + k + (n > 1 ? " ×" + std::to_string(n) : "");
    deck.summary += "\n";
  }
  return deck;
}

GmshDeck gmsh_to_keywords(const std::string& text, const std::string& name) {
  Lines in(text, name);
  Mesh mesh;
  bool format = false;
  while (!in.done()) {
    const auto t = in.next("a section");
    if (t.empty()) continue;
    if (t[0][0] != '$') in.fail("expected a section ($MeshFormat, $Nodes, ...), found '" + t[0] + "'");
    if (!format && t[0] != "$MeshFormat") in.fail("a gmsh mesh begins with $MeshFormat");
    format = true;
    read_section(in, t[0], mesh);
  }
  if (!format) throw InputError({name, 1}, "an empty file: not a gmsh mesh");

  // The physical groups of each element: 2.2 names one per element, 4.1
  // those of its entity. Without physical volumes, each volume entity is a part.
  auto physicals_of = [&](const Element& e) -> std::vector<int> {
    if (mesh.version == 2.2) return e.physical ? std::vector<int>{e.physical} : std::vector<int>{};
    const auto it = mesh.entity_physicals.find({e.dim, e.entity});
    return it == mesh.entity_physicals.end() ? std::vector<int>{} : it->second;
  };
  bool physical_volumes = false;
  for (const Element& e : mesh.elements)
    if (e.dim == 3 && !physicals_of(e).empty()) physical_volumes = true;
  Groups g;
  g.part_of.assign(mesh.elements.size(), 0);
  g.surfaces_of.resize(mesh.elements.size());
  for (size_t k = 0; k < mesh.elements.size(); ++k) {
    const Element& e = mesh.elements[k];
    const std::vector<int> ph = physicals_of(e);
    if (e.dim == 3) {
      if (ph.size() > 1)
        throw InputError({name, e.line}, "volume entity " + std::to_string(e.entity) + " is in " +
                                             std::to_string(ph.size()) + " physical volumes: an element belongs to one part");
      g.part_of[k] = physical_volumes ? (ph.empty() ? 0 : ph[0]) : e.entity;
    } else if (e.dim == 2) {
      g.surfaces_of[k] = ph;
    }
  }
  for (const auto& [key, nm] : mesh.physical_names)
    (key.first == 3 ? g.part_names : g.surface_names)[key.second] = nm;
  if (!physical_volumes) g.part_names.clear();
  return keywords_of(mesh, g, name, "--from-gmsh");
}

}  // namespace fe
