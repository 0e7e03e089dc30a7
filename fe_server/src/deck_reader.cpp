#include "deck_reader.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace fe {

using config::Block;
using config::Card;
using config::InputError;

int Model::index_of(int node_id, const config::SourceLocation& where) const {
  auto it = node_index.find(node_id);
  if (it == node_index.end()) throw InputError(where, "node " + std::to_string(node_id) + " is not defined in *NODE");
  return it->second;
}

double Model::total_mass() const {
  double m = 0;
  for (double mi : mass) m += mi;
  return m;
}

namespace {

// Fields of a card: comma-separated as written, else fixed-width columns.
Card fields_of(const Card& c, const std::vector<int>& widths) {
  if (c.comma_separated) return c;
  Card out = c;
  out.fields = config::split_fixed(c.text, widths);
  return out;
}
const std::vector<int> kW10 = {10};

struct PartInfo {
  int secid = 0, mid = 0;
  config::SourceLocation where;
};
struct SpringMaterial {
  double k = 0.0, c = 0.0;
};

}  // namespace

Model parse_deck(const std::string& text, const std::string& name, DeckWarnings* warnings) {
  {
    Model m;
    m.source = name;
    auto blocks = config::parse_keyword_text(text, name, true);
    std::map<int, PartInfo> parts;
    std::map<int, SpringMaterial> spring_mats;
    std::vector<Card> discrete_cards, mass_cards, spc_cards, vel_cards, rigid_cards;
    // Keywords whose absence of support would change the physics are errors.
    const std::set<std::string> must_understand = {"*ELEMENT_SOLID", "*ELEMENT_SHELL", "*ELEMENT_BEAM",
                                                   "*LOAD_SEGMENT_SET", "*LOAD_NODE_SET", "*MAT_ELASTIC",
                                                   "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE"};
    bool seen_keyword = false;
    for (const Block& b : blocks) {
      const std::string& kw = b.keyword;
      if (kw == "*KEYWORD") {
        seen_keyword = true;
      } else if (kw == "*END") {
        break;
      } else if (kw == "*TITLE") {
        if (!b.cards.empty()) m.title = config::trim(b.cards[0].text);
      } else if (kw == "*NODE") {
        for (const Card& raw : b.cards) {
          Card c = fields_of(raw, {8, 16, 16, 16, 8, 8});
          int id = static_cast<int>(c.integer(0, "NID"));
          if (m.node_index.count(id)) c.fail("node " + std::to_string(id) + " defined twice");
          m.node_index[id] = static_cast<int>(m.node_ids.size());
          m.node_ids.push_back(id);
          m.x0.emplace_back(c.real_or(1, "X", 0), c.real_or(2, "Y", 0), c.real_or(3, "Z", 0));
          long tc = c.integer_or(4, "TC", 0);
          Eigen::Matrix<bool, 3, 1> f(tc == 1 || tc == 4 || tc == 5 || tc == 7,
                                      tc == 2 || tc == 4 || tc == 6 || tc == 7,
                                      tc == 3 || tc == 5 || tc == 6 || tc == 7);
          m.fixed.push_back(f);
        }
      } else if (kw == "*PART") {
        // Card 1: title; card 2: PID, SECID, MID, ...
        for (size_t i = 0; i + 1 < b.cards.size(); i += 2) {
          Card c = fields_of(b.cards[i + 1], kW10);
          PartInfo p{static_cast<int>(c.integer_or(1, "SECID", 0)), static_cast<int>(c.integer_or(2, "MID", 0)), c.where};
          parts[static_cast<int>(c.integer(0, "PID"))] = p;
        }
        if (b.cards.size() % 2) b.fail("*PART needs a title card and a PID card per part");
      } else if (kw == "*SECTION_DISCRETE") {
        for (const Card& raw : b.cards) {
          Card c = fields_of(raw, kW10);
          if (c.fields.size() >= 2 && c.integer_or(1, "DRO", 0) != 0)
            c.fail("only translational discrete elements (DRO = 0) are supported");
        }
      } else if (kw == "*MAT_SPRING_ELASTIC" || kw == "*MAT_S01") {
        for (const Card& raw : b.cards) {
          Card c = fields_of(raw, kW10);
          spring_mats[static_cast<int>(c.integer(0, "MID"))].k = c.real(1, "K");
        }
      } else if (kw == "*MAT_DAMPER_VISCOUS" || kw == "*MAT_S02") {
        for (const Card& raw : b.cards) {
          Card c = fields_of(raw, kW10);
          spring_mats[static_cast<int>(c.integer(0, "MID"))].c = c.real(1, "DC");
        }
      } else if (kw == "*ELEMENT_DISCRETE") {
        for (const Card& raw : b.cards) discrete_cards.push_back(fields_of(raw, {8, 8, 8, 8, 8, 16, 8, 16}));
      } else if (kw == "*ELEMENT_MASS") {
        for (const Card& raw : b.cards) mass_cards.push_back(fields_of(raw, {8, 8, 16, 8}));
      } else if (kw == "*SET_NODE_LIST") {
        if (b.cards.empty()) b.fail("*SET_NODE_LIST needs a header card with SID");
        int sid = static_cast<int>(fields_of(b.cards[0], kW10).integer(0, "SID"));
        auto& list = m.node_sets[sid];
        for (size_t i = 1; i < b.cards.size(); ++i) {
          Card c = fields_of(b.cards[i], kW10);
          for (size_t k = 0; k < c.fields.size(); ++k)
            if (!c.fields[k].empty()) {
              long id = c.integer(k, "NID");
              if (id != 0) list.push_back(static_cast<int>(id));
            }
        }
      } else if (kw == "*SET_SEGMENT") {
        if (b.cards.empty()) b.fail("*SET_SEGMENT needs a header card with SID");
        int sid = static_cast<int>(fields_of(b.cards[0], kW10).integer(0, "SID"));
        auto& list = m.segment_sets[sid];
        for (size_t i = 1; i < b.cards.size(); ++i) {
          Card c = fields_of(b.cards[i], kW10);
          Segment s;
          for (int k = 0; k < 4; ++k) {
            long id = c.integer_or(static_cast<size_t>(k), "N", k == 3 ? 0 : -1);
            if (k == 3 && id == 0) {
              s.n[3] = s.n[2];  // triangle
              continue;
            }
            s.n[k] = m.index_of(static_cast<int>(id), c.where);
          }
          list.push_back(s);
        }
      } else if (kw == "*CONSTRAINED_NODAL_RIGID_BODY") {
        for (const Card& raw : b.cards) rigid_cards.push_back(fields_of(raw, kW10));
      } else if (kw == "*BOUNDARY_SPC_NODE") {
        for (const Card& raw : b.cards) spc_cards.push_back(fields_of(raw, kW10));
      } else if (kw == "*INITIAL_VELOCITY_NODE") {
        for (const Card& raw : b.cards) vel_cards.push_back(fields_of(raw, kW10));
      } else if (kw == "*USER_LOADING_SET") {
        // Co-simulation port on a segment set: SID, LTYPE (PRESSS), PORT.
        for (const Card& raw : b.cards) {
          Card c = fields_of(raw, kW10);
          LoadingSet ls;
          ls.segment_set = static_cast<int>(c.integer(0, "SID"));
          std::string ltype = config::to_upper(c.field(1, "LTYPE"));
          if (ltype != "PRESSS") c.fail("LTYPE '" + c.fields[1] + "': only PRESSS (pressure on a segment set) is supported");
          ls.port_id = static_cast<int>(c.integer(2, "PORT"));
          ls.where = c.where;
          m.loading_sets.push_back(ls);
        }
      } else if (kw == "*CONTROL_TERMINATION") {
        if (!b.cards.empty()) m.end_time = fields_of(b.cards[0], kW10).real(0, "ENDTIM");
      } else if (kw == "*CONTROL_TIMESTEP") {
        if (!b.cards.empty()) {
          double s = fields_of(b.cards[0], kW10).real_or(1, "TSSFAC", 0.9);
          if (s > 0.0) m.dt_scale = s;
        }
      } else if (kw == "*DATABASE_HISTORY_NODE") {
        for (const Card& raw : b.cards) {
          Card c = fields_of(raw, kW10);
          for (size_t k = 0; k < c.fields.size(); ++k)
            if (!c.fields[k].empty() && c.integer(k, "ID") != 0)
              m.history_nodes.push_back(m.index_of(static_cast<int>(c.integer(k, "ID")), c.where));
        }
      } else if (must_understand.count(kw)) {
        b.fail(kw + " is not supported by this fe_server version; ignoring it would change the physics");
      } else if (warnings) {
        warnings->messages.push_back(b.where.str() + ": warning: keyword " + kw + " is not supported and was ignored");
      }
    }
    if (!seen_keyword && warnings)
      warnings->messages.push_back(name + ":1: warning: the deck does not start with *KEYWORD");
    if (m.node_ids.empty()) throw InputError({name, 1}, "the deck defines no nodes (*NODE)");

    const size_t n = m.node_ids.size();
    m.mass.assign(n, 0.0);
    m.v0.assign(n, Vec3::Zero());
    for (const Card& c : mass_cards) {
      double mass = c.real(2, "MASS");
      if (!(mass > 0.0)) c.fail("MASS must be positive");
      m.mass[static_cast<size_t>(m.index_of(static_cast<int>(c.integer(1, "NID")), c.where))] += mass;
    }
    for (const Card& c : discrete_cards) {
      DiscreteElement d;
      d.where = c.where;
      d.id = static_cast<int>(c.integer(0, "EID"));
      int pid = static_cast<int>(c.integer(1, "PID"));
      d.n1 = m.index_of(static_cast<int>(c.integer(2, "N1")), c.where);
      d.n2 = m.index_of(static_cast<int>(c.integer(3, "N2")), c.where);
      double scale = c.real_or(5, "S", 1.0);
      if (scale == 0.0) scale = 1.0;  // LS-DYNA: S = 0 means 1
      d.offset = c.real_or(7, "OFFSET", 0.0);
      auto p = parts.find(pid);
      if (p == parts.end()) c.fail("part " + std::to_string(pid) + " is not defined in *PART");
      auto mat = spring_mats.find(p->second.mid);
      if (mat == spring_mats.end())
        c.fail("part " + std::to_string(pid) + " has material " + std::to_string(p->second.mid) +
               ", which is not a *MAT_SPRING_ELASTIC or *MAT_DAMPER_VISCOUS");
      d.k = scale * mat->second.k;
      d.c = scale * mat->second.c;
      d.length0 = (m.x0[static_cast<size_t>(d.n2)] - m.x0[static_cast<size_t>(d.n1)]).norm();
      if (d.length0 <= 0.0) c.fail("discrete element " + std::to_string(d.id) + " has zero length: its direction is undefined");
      m.discretes.push_back(d);
    }
    for (const Card& c : spc_cards) {
      size_t i = static_cast<size_t>(m.index_of(static_cast<int>(c.integer(0, "NID")), c.where));
      for (int k = 0; k < 3; ++k)
        if (c.integer_or(static_cast<size_t>(2 + k), "DOF", 0) != 0) m.fixed[i][k] = true;
    }
    for (const Card& c : vel_cards) {
      size_t i = static_cast<size_t>(m.index_of(static_cast<int>(c.integer(0, "NID")), c.where));
      m.v0[i] = Vec3(c.real_or(1, "VX", 0), c.real_or(2, "VY", 0), c.real_or(3, "VZ", 0));
    }
    std::set<int> in_body;
    for (const Card& c : rigid_cards) {
      RigidBody rb;
      rb.where = c.where;
      rb.id = static_cast<int>(c.integer(0, "PID"));
      int nsid = static_cast<int>(c.integer(2, "NSID"));
      auto set = m.node_sets.find(nsid);
      if (set == m.node_sets.end()) c.fail("node set " + std::to_string(nsid) + " is not defined in *SET_NODE_LIST");
      for (int id : set->second) {
        int idx = m.index_of(id, c.where);
        if (!in_body.insert(idx).second) c.fail("node " + std::to_string(id) + " belongs to two rigid bodies");
        rb.nodes.push_back(idx);
        rb.mass += m.mass[static_cast<size_t>(idx)];
      }
      if (!(rb.mass > 0.0)) c.fail("rigid body " + std::to_string(rb.id) + " has no mass (add *ELEMENT_MASS to one of its nodes)");
      m.rigid_bodies.push_back(rb);
    }
    for (size_t i = 0; i < n; ++i) {
      bool all_fixed = m.fixed[i].all();
      if (!in_body.count(static_cast<int>(i)) && !all_fixed && !(m.mass[i] > 0.0))
        throw InputError({name, 1}, "node " + std::to_string(m.node_ids[i]) +
                                        " has no mass and is neither fixed nor part of a rigid body");
    }
    for (const auto& ls : m.loading_sets)
      if (!m.segment_sets.count(ls.segment_set))
        throw InputError(ls.where, "segment set " + std::to_string(ls.segment_set) + " is not defined in *SET_SEGMENT");
    return m;
  }
}

Model read_deck(const std::string& path, DeckWarnings* warnings) {
  return parse_deck(config::read_text_file(path, "deck"), path, warnings);
}

}  // namespace fe
