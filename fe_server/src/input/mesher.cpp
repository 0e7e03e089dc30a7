#include "input/mesher.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

namespace fe {

namespace {

struct Point2 {
  double x, y;
};

// The 2D O-grid: node positions and quads (counter-clockwise seen from +z),
// each quad with the mean radius of its ring (0 for the core).
struct CrossSection {
  std::vector<Point2> nodes;
  std::vector<std::array<int, 4>> quads;
  // Nominal radius of each cell's ring (mid-way between its ring boundaries;
  // 0 for the core). Sections are assigned by it, not by the cell centroid,
  // whose radius shrinks by cos(Δθ/2) on a coarse ring and would put an outer
  // ring's cells into the section inside it.
  std::vector<double> quad_radius;
};

CrossSection o_grid(const std::vector<double>& radii, double h) {
  // Cells around: at least one per h of the outer circumference, so the
  // polygon's area stays within ~1 % of the circle's (a 20-gon holds 98.4 %).
  CrossSection cs;
  const double r1 = radii.front();
  // Core square of half-side a, so its corners sit at 0.75·r1 and its edge
  // midpoints at 0.53·r1: cells of the first ring stay reasonably shaped.
  const double a = 0.75 * r1 / std::sqrt(2.0);
  const int n = std::max({1, static_cast<int>(std::lround(2.0 * a / h)),
                          static_cast<int>(std::ceil(2.0 * M_PI * radii.back() / (4.0 * h)))});  // cells per core side
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) cs.nodes.push_back({-a + 2.0 * a * i / n, -a + 2.0 * a * j / n});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      cs.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      cs.quad_radius.push_back(0.0);
    }
  // The core's boundary, counter-clockwise from the (−a, −a) corner: 4n nodes.
  std::vector<int> ring;
  for (int i = 0; i < n; ++i) ring.push_back(id(i, 0));
  for (int j = 0; j < n; ++j) ring.push_back(id(n, j));
  for (int i = n; i > 0; --i) ring.push_back(id(i, n));
  for (int j = n; j > 0; --j) ring.push_back(id(0, j));
  const size_t m = ring.size();
  std::vector<Point2> square(m);
  for (size_t k = 0; k < m; ++k) square[k] = cs.nodes[static_cast<size_t>(ring[k])];
  // Rings: the first blends the square into the circle r1, the rest are circles.
  double r_prev = 0.0, r_nominal = 0.5 * r1;  // the core's edge, nominally
  for (size_t level = 0; level < radii.size(); ++level) {
    const double r = radii[level];
    const double span = level == 0 ? r - 0.5 * r1 : r - r_prev;
    const int layers = std::max(1, static_cast<int>(std::lround(span / h)));
    for (int l = 1; l <= layers; ++l) {
      const double s = static_cast<double>(l) / layers;
      std::vector<int> next(m);
      for (size_t k = 0; k < m; ++k) {
        const double theta = std::atan2(square[k].y, square[k].x);
        Point2 p;
        if (level == 0) {
          const Point2 c{r * std::cos(theta), r * std::sin(theta)};
          p = {(1 - s) * square[k].x + s * c.x, (1 - s) * square[k].y + s * c.y};
        } else {
          const double rr = r_prev + s * (r - r_prev);
          p = {rr * std::cos(theta), rr * std::sin(theta)};
        }
        next[k] = static_cast<int>(cs.nodes.size());
        cs.nodes.push_back(p);
      }
      const double r_next = level == 0 ? (1 - s) * 0.5 * r1 + s * r : r_prev + s * (r - r_prev);
      for (size_t k = 0; k < m; ++k) {
        const size_t k1 = (k + 1) % m;
        // Counter-clockwise: out along θ_k, forward on the outer arc, back in on θ_k+1.
        cs.quads.push_back({ring[k], next[k], next[k1], ring[k1]});
        cs.quad_radius.push_back(0.5 * (r_nominal + r_next));
      }
      r_nominal = r_next;
      ring = next;
    }
    r_prev = r;
  }
  return cs;
}

}  // namespace

std::vector<RevolutionSection> parse_sections(const std::string& text_in) {
  std::vector<RevolutionSection> out;
  std::string text = text_in;
  std::replace(text.begin(), text.end(), '/', ';');  // '/' separates sections too (shell- and CMake-safe)
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ';')) {
    std::vector<double> v;
    std::stringstream is(item);
    std::string num;
    while (std::getline(is, num, ',')) {
      if (num.find_first_not_of(" \t") == std::string::npos) continue;
      v.push_back(std::stod(num));
    }
    if (v.empty()) continue;
    if (v.size() < 2 || v.size() > 3) throw std::invalid_argument("section '" + item + "': expected L,r_out[,r_in]");
    out.push_back({v[0], v[1], v.size() == 3 ? v[2] : 0.0});
  }
  return out;
}

namespace {

// Stations along the axis: every section cut into layers of about the axial
// size; which section each layer belongs to; the station where each section
// starts (and, last, where the body ends).
struct AxialStations {
  std::vector<double> at;
  std::vector<size_t> section_of_layer;
  std::vector<size_t> first_station = {0};
};
AxialStations axial_stations(const std::vector<RevolutionSection>& sections, const RevolutionMeshOptions& opt) {
  AxialStations st;
  st.at = {opt.z0};
  const double h = opt.axial_size > 0.0 ? opt.axial_size : opt.element_size;
  for (size_t i = 0; i < sections.size(); ++i) {
    const int n = std::max(1, static_cast<int>(std::lround(sections[i].length / h)));
    const double start = st.at.back();
    for (int k = 1; k <= n; ++k) {
      st.at.push_back(k == n ? start + sections[i].length : start + sections[i].length * k / n);
      st.section_of_layer.push_back(i);
    }
    st.first_station.push_back(st.at.size() - 1);
  }
  return st;
}

// Every exposed face normal to the axis: at each section boundary, facing −axis
// the part of the section above not covered by the one below (own, other),
// facing +axis the reverse. fn(station, direction, own, other-or-null).
template <class Fn>
void for_each_axial_face(const std::vector<RevolutionSection>& sections, const AxialStations& st, Fn fn) {
  for (size_t k = 0; k < st.first_station.size(); ++k) {
    const RevolutionSection* below = k > 0 ? &sections[k - 1] : nullptr;
    const RevolutionSection* above = k < sections.size() ? &sections[k] : nullptr;
    for (int dir : {-1, +1}) {
      const RevolutionSection* own = dir < 0 ? above : below;
      const RevolutionSection* other = dir < 0 ? below : above;
      if (own) fn(st.first_station[k], dir, *own, other);
    }
  }
}

// Deck ids for the raw node numbers the elements use, in order, after `offset`.
template <size_t N>
std::map<long, int> number_nodes(const std::vector<std::array<long, N>>& elems, int offset) {
  std::map<long, int> number;
  for (const auto& e : elems)
    for (long n : e) number.emplace(n, 0);
  for (auto& [raw, id] : number) id = ++offset;
  return number;
}

// The comment lines that open a mesh file: what made it, and its sections.
void write_header(std::ostream& k, const std::string& title, const char* how,
                  const std::vector<RevolutionSection>& sections) {
  k << "$ " << title << ": generated by " << how << "\n$ sections (length, r_out, r_in):";
  for (const auto& s : sections) k << " (" << s.length << ", " << s.r_out << ", " << s.r_in << ")";
  k << "\n";
}

// A keyword's list of ids, eight to a card.
void write_ids(std::ostream& k, const std::vector<int>& ids) {
  for (size_t i = 0; i < ids.size(); ++i) k << ids[i] << ((i % 8 == 7 || i + 1 == ids.size()) ? "\n" : ",");
}

}  // namespace

RevolutionMesh mesh_revolution(const std::vector<RevolutionSection>& sections, const RevolutionMeshOptions& opt) {
  if (sections.empty()) throw std::invalid_argument("no sections");
  if (!(opt.element_size > 0.0)) throw std::invalid_argument("element size must be positive");
  std::set<double> rset;
  for (size_t i = 0; i < sections.size(); ++i) {
    const auto& s = sections[i];
    if (!(s.length > 0.0) || !(s.r_out > 0.0) || s.r_in < 0.0 || !(s.r_in < s.r_out))
      throw std::invalid_argument("section " + std::to_string(i + 1) + ": need length > 0 and 0 ≤ r_in < r_out");
    rset.insert(s.r_out);
    if (s.r_in > 0.0) rset.insert(s.r_in);
  }
  const std::vector<double> radii(rset.begin(), rset.end());
  const CrossSection cs = o_grid(radii, opt.element_size);
  const size_t np = cs.nodes.size();

  // Which cells each section takes: those between its radii.
  auto inside = [&](size_t q, const RevolutionSection& s) {
    const double r = cs.quad_radius[q];
    return r < s.r_out && (s.r_in == 0.0 ? true : r > s.r_in);
  };
  // Axial stations.
  const AxialStations stations = axial_stations(sections, opt);
  const std::vector<double>& z = stations.at;
  const std::vector<size_t>& section_of_layer = stations.section_of_layer;
  // Elements; node id = offset + station·np + 2D index + 1, renumbered to used ones below.
  std::vector<std::array<long, 8>> elems;
  for (size_t layer = 0; layer < section_of_layer.size(); ++layer) {
    const auto& s = sections[section_of_layer[layer]];
    for (size_t q = 0; q < cs.quads.size(); ++q) {
      if (!inside(q, s)) continue;
      std::array<long, 8> e;
      for (int k = 0; k < 4; ++k) {
        e[static_cast<size_t>(k)] = static_cast<long>(layer * np) + cs.quads[q][static_cast<size_t>(k)];
        e[static_cast<size_t>(k + 4)] = static_cast<long>((layer + 1) * np) + cs.quads[q][static_cast<size_t>(k)];
      }
      elems.push_back(e);
    }
  }
  std::map<long, int> number = number_nodes(elems, opt.node_offset);

  RevolutionMesh out;
  std::ostringstream k;
  char buf[160];
  write_header(k, opt.title, "fe_mesh (body of revolution about z)", sections);
  k << "*NODE\n";
  for (const auto& [raw, id] : number) {
    const auto& p = cs.nodes[static_cast<size_t>(raw) % np];
    std::snprintf(buf, sizeof buf, "%d,%.10g,%.10g,%.10g\n", id, p.x, p.y, z[static_cast<size_t>(raw) / np]);
    k << buf;
  }
  k << "*ELEMENT_SOLID\n";
  int eid = opt.element_offset;
  for (const auto& e : elems) {
    k << ++eid << "," << opt.part;
    for (long n : e) k << "," << number[n];
    k << "\n";
  }
  // Gauge layers: the elements of the layer that contains each gauge z.
  for (double zg : opt.gauges) {
    std::vector<int> ids;
    int e2 = opt.element_offset;
    for (size_t layer = 0; layer < section_of_layer.size(); ++layer)
      for (size_t q = 0; q < cs.quads.size(); ++q) {
        if (!inside(q, sections[section_of_layer[layer]])) continue;
        ++e2;
        if (z[layer] <= zg && zg < z[layer + 1]) ids.push_back(e2);
      }
    if (ids.empty()) throw std::invalid_argument("gauge z = " + std::to_string(zg) + " is outside the body");
    std::snprintf(buf, sizeof buf, "$ gauge layer at z = %.6g\n*DATABASE_HISTORY_SOLID\n", zg);
    k << buf;
    write_ids(k, ids);
  }
  // Exposed axial faces, grouped per station and direction.
  int sid = opt.set_offset;
  for_each_axial_face(sections, stations, [&](size_t station, int dir, const RevolutionSection& own,
                                              const RevolutionSection* other) {
    std::vector<std::array<int, 4>> segs;
    double r_lo = 1e300, r_hi = 0.0;
    for (size_t q = 0; q < cs.quads.size(); ++q) {
      if (!inside(q, own) || (other && inside(q, *other))) continue;
      const auto& quad = cs.quads[q];
      std::array<int, 4> seg;
      for (int c = 0; c < 4; ++c) seg[static_cast<size_t>(c)] = number[static_cast<long>(station * np) + quad[static_cast<size_t>(c)]];
      if (dir < 0) std::swap(seg[1], seg[3]);  // clockwise from +z: the normal points to −z
      segs.push_back(seg);
      for (int c = 0; c < 4; ++c) {
        const auto& p = cs.nodes[static_cast<size_t>(quad[static_cast<size_t>(c)])];
        const double r = std::hypot(p.x, p.y);
        r_lo = std::min(r_lo, r);
        r_hi = std::max(r_hi, r);
      }
    }
    if (segs.empty()) return;
    if (r_lo < 0.5 * radii.front()) r_lo = 0.0;  // a full disc (the core has no node on the axis)
    ++sid;
    out.faces.push_back({sid, z[station], dir, r_lo, r_hi});
    std::snprintf(buf, sizeof buf, "$ set %d: face at z = %.6g facing %sz, r %.6g to %.6g\n", sid, z[station],
                  dir < 0 ? "-" : "+", r_lo, r_hi);
    k << buf << "*SET_SEGMENT\n" << sid << "\n";
    for (const auto& sg : segs) k << sg[0] << "," << sg[1] << "," << sg[2] << "," << sg[3] << "\n";
  });
  out.keyword_text = k.str();
  out.nodes = static_cast<int>(number.size());
  out.elements = static_cast<int>(elems.size());
  return out;
}

namespace {
// Cell boundaries over [a, b] of about h, each cell `growth` times the one
// before it (1: uniform).
std::vector<double> graded(double a, double b, double h, double growth) {
  std::vector<double> out = {a};
  const int n = std::max(1, static_cast<int>(std::lround((b - a) / h)));
  if (!(growth > 1.0 + 1e-12)) {
    for (int i = 1; i <= n; ++i) out.push_back(a + (b - a) * i / n);
    // Exactly b: a + (b − a)·n/n can miss it by an ulp, and a section's
    // radius that its own station misses has no node on it (r = 26.8537 mm
    // did: the outer-surface set then looked past the section's nodes).
    out.back() = b;
    return out;
  }
  double sum = 0.0, w = 1.0;
  for (int i = 0; i < n; ++i, w *= growth) sum += w;
  double x = a;
  w = 1.0;
  for (int i = 0; i < n; ++i, w *= growth) out.push_back(x += (b - a) * w / sum);
  out.back() = b;
  return out;
}
}  // namespace

RevolutionMesh mesh_axisymmetric(const std::vector<RevolutionSection>& sections, const RevolutionMeshOptions& opt) {
  if (sections.empty()) throw std::invalid_argument("no sections");
  if (!(opt.element_size > 0.0)) throw std::invalid_argument("element size must be positive");
  if (!(opt.radial_growth >= 1.0) || opt.radial_growth > 10.0)
    throw std::invalid_argument("radial growth must be from 1 to 10");
  std::set<double> rset = {0.0};
  for (size_t i = 0; i < sections.size(); ++i) {
    const auto& s = sections[i];
    if (!(s.length > 0.0) || !(s.r_out > 0.0) || s.r_in < 0.0 || !(s.r_in < s.r_out))
      throw std::invalid_argument("section " + std::to_string(i + 1) + ": need length > 0 and 0 ≤ r_in < r_out");
    rset.insert(s.r_out);
    rset.insert(s.r_in);
  }
  const double r_max = *rset.rbegin();
  for (double r : opt.radii) {
    if (!(r > 0.0 && r < r_max)) throw std::invalid_argument("extra radius " + std::to_string(r) + " is outside the body");
    rset.insert(r);
  }
  // Radial stations: every radius of the table, cells of about h between them.
  std::vector<double> r = {0.0};
  for (auto it = std::next(rset.begin()); it != rset.end(); ++it) {
    const std::vector<double> part = graded(r.back(), *it, opt.element_size, opt.radial_growth);
    r.insert(r.end(), part.begin() + 1, part.end());
  }
  const size_t nr = r.size();
  auto inside = [&](size_t cell, const RevolutionSection& s) {
    const double rm = 0.5 * (r[cell] + r[cell + 1]);
    return rm < s.r_out && rm > s.r_in;
  };
  const AxialStations stations = axial_stations(sections, opt);
  const std::vector<double>& y = stations.at;
  const std::vector<size_t>& section_of_layer = stations.section_of_layer;
  // Elements; raw node number = station·nr + radial index, renumbered below.
  std::vector<std::array<long, 4>> elems;
  std::vector<size_t> elem_layer;
  for (size_t layer = 0; layer < section_of_layer.size(); ++layer)
    for (size_t c = 0; c + 1 < nr; ++c) {
      if (!inside(c, sections[section_of_layer[layer]])) continue;
      const long a = static_cast<long>(layer * nr + c), b = static_cast<long>((layer + 1) * nr + c);
      elems.push_back({a, a + 1, b + 1, b});  // counter-clockwise in (r, y)
      elem_layer.push_back(layer);
    }
  std::map<long, int> number = number_nodes(elems, opt.node_offset);

  RevolutionMesh out;
  std::ostringstream k;
  char buf[160];
  write_header(k, opt.title, "fe_mesh --axisymmetric (x the radius, y the axis)", sections);
  k << "*NODE\n";
  for (const auto& [raw, id] : number) {
    std::snprintf(buf, sizeof buf, "%d,%.10g,%.10g,0\n", id, r[static_cast<size_t>(raw) % nr],
                  y[static_cast<size_t>(raw) / nr]);
    k << buf;
  }
  k << "*ELEMENT_SHELL\n";
  int eid = opt.element_offset;
  for (const auto& e : elems) {
    k << ++eid << "," << opt.part;
    for (long n : e) k << "," << number[n];
    k << "\n";
  }
  int gauge_number = 0;
  for (double yg : opt.gauges) {
    std::vector<int> ids;
    for (size_t i = 0; i < elems.size(); ++i)
      if (y[elem_layer[i]] <= yg && yg < y[elem_layer[i] + 1]) ids.push_back(opt.element_offset + static_cast<int>(i) + 1);
    if (ids.empty()) throw std::invalid_argument("gauge y = " + std::to_string(yg) + " is outside the body");
    if (!opt.gauge_cut_only) {
      std::snprintf(buf, sizeof buf, "$ gauge layer at y = %.6g\n*DATABASE_HISTORY_SHELL\n", yg);
      k << buf;
      write_ids(k, ids);
    }
    // A cut through the layer's lower edge: its nodes and the layer's
    // elements (above the cut) as *DATABASE_CROSS_SECTION_SET, id set offset
    // + 100 + gauge number: the force through the section (σ integrated over
    // the ring exactly) and the cut's mean velocity, which separate the
    // down- and up-going waves.
    const int cut = opt.set_offset + 100 + ++gauge_number;
    std::set<int> lower;
    for (int id : ids) {
      const auto& e = elems[static_cast<size_t>(id - opt.element_offset - 1)];
      lower.insert(number[e[0]]), lower.insert(number[e[1]]);
    }
    std::snprintf(buf, sizeof buf, "$ cross section %d at y = %.6g (the gauge layer's lower edge)\n*SET_NODE_LIST\n%d\n",
                  cut, y[elem_layer[static_cast<size_t>(ids.front() - opt.element_offset - 1)]], cut);
    k << buf;
    write_ids(k, {lower.begin(), lower.end()});
    k << "*SET_SHELL_LIST\n" << cut << "\n";
    write_ids(k, ids);
    k << "*DATABASE_CROSS_SECTION_SET\n$ nsid, hsid, bsid, ssid, tsid, dsid, id\n"
      << cut << ",0,0," << cut << ",0,0," << cut << "\n";
  }
  // Exposed faces normal to the axis, per station and direction, as lines
  // with the body on their left: facing −y runs outwards, facing +y inwards.
  int sid = opt.set_offset;
  for_each_axial_face(sections, stations, [&](size_t station, int dir, const RevolutionSection& own,
                                              const RevolutionSection* other) {
    std::vector<std::array<int, 2>> segs;
    double r_lo = 1e300, r_hi = 0.0;
    for (size_t c = 0; c + 1 < nr; ++c) {
      if (!inside(c, own) || (other && inside(c, *other))) continue;
      const int a = number[static_cast<long>(station * nr + c)], b = number[static_cast<long>(station * nr + c + 1)];
      segs.push_back(dir < 0 ? std::array<int, 2>{a, b} : std::array<int, 2>{b, a});
      r_lo = std::min(r_lo, r[c]);
      r_hi = std::max(r_hi, r[c + 1]);
    }
    if (segs.empty()) return;
    ++sid;
    out.faces.push_back({sid, y[station], dir, r_lo, r_hi});
    std::snprintf(buf, sizeof buf, "$ set %d: face at y = %.6g facing %sy, r %.6g to %.6g\n", sid, y[station],
                  dir < 0 ? "-" : "+", r_lo, r_hi);
    k << buf << "*SET_SEGMENT\n" << sid << "\n";
    for (const auto& s2 : segs) k << s2[0] << "," << s2[1] << "\n";
    // The face's nodes too (node set 20 above the segment set's id): a
    // support plate (*CONSTRAINED_NODAL_RIGID_BODY) or a feed sits there.
    std::set<int> face_nodes;
    for (const auto& s2 : segs) face_nodes.insert(s2[0]), face_nodes.insert(s2[1]);
    k << "*SET_NODE_LIST\n" << sid + 20 << "\n";
    write_ids(k, {face_nodes.begin(), face_nodes.end()});
  });
  // Each section's outer cylindrical surface as a node set (id: set offset +
  // section number): where a guide's friction, a feed force or a position
  // monitor sits on a deformable body.
  for (size_t i = 0; i < sections.size(); ++i) {
    size_t c_out = 0;
    while (c_out + 1 < nr && r[c_out] < sections[i].r_out) ++c_out;
    std::vector<int> ids;
    for (size_t st = stations.first_station[i]; st <= stations.first_station[i + 1]; ++st)
      ids.push_back(number.at(static_cast<long>(st * nr + c_out)));
    std::snprintf(buf, sizeof buf, "$ node set %d: outer surface of section %zu, r = %.6g, y %.6g to %.6g\n",
                  opt.set_offset + static_cast<int>(i) + 1, i + 1, r[c_out], y[stations.first_station[i]],
                  y[stations.first_station[i + 1]]);
    k << buf << "*SET_NODE_LIST\n" << opt.set_offset + static_cast<int>(i) + 1 << "\n";
    write_ids(k, ids);
  }
  out.keyword_text = k.str();
  out.nodes = static_cast<int>(number.size());
  out.elements = static_cast<int>(elems.size());
  return out;
}

}  // namespace fe
