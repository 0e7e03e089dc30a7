#include "input/deck_reader.hpp"
#include "input/deck_grammar.hpp"

#include "elements/element_axi4.hpp"
#include "elements/element_hex8.hpp"
#include "elements/element_tet4.hpp"
#include "config/nearest.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <sstream>

namespace fe {

using config::Block;
using config::Card;
using config::InputError;

namespace {

// Fields of a card: comma-separated as written, else fixed-width columns.
Card fields_of(const Card& c, const std::vector<int>& widths) {
  if (c.comma_separated) return c;
  Card out = c;
  out.fields = config::split_fixed(c.text, widths);
  return out;
}
const std::vector<int> kW10 = {10};
const std::vector<int> kW8 = {8};

// All ids listed on the cards of a list keyword (8 per card, 0 or blank ends).
std::vector<int> id_list(const Block& b, size_t first_card, const char* what) {
  std::vector<int> ids;
  for (size_t i = first_card; i < b.cards.size(); ++i) {
    Card c = fields_of(b.cards[i], kW10);
    for (size_t k = 0; k < c.fields.size(); ++k)
      if (!c.fields[k].empty()) {
        long id = c.integer(k, what);
        if (id != 0) ids.push_back(static_cast<int>(id));
      }
  }
  return ids;
}

// Keywords this reader reads; anything else is a warning (or an error, below).
struct Reader {
  Reader(Model& model, DeckWarnings* w) : m(model), warnings(w) {}
  Model& m;
  DeckWarnings* warnings;
  std::map<int, std::pair<double, double>> spring_mats;  // mid → (k, c)
  std::vector<std::pair<Card, bool>> motion_cards;
  std::vector<std::pair<Card, bool>> pressure_cards;  // *LOAD_SEGMENT card, and whether _SET
  std::vector<std::pair<Card, bool>> nodal_load_cards;  // *LOAD_NODE card, and whether _SET
  std::vector<std::pair<Card, bool>> extra_node_cards;  // *CONSTRAINED_EXTRA_NODES card, and whether _SET
  std::vector<Card> merge_cards;                        // *CONSTRAINED_RIGID_BODIES
  std::vector<std::pair<int, Card>> hardening_curves;   // *MAT_024 with LCSS: material id, card 2
  struct DampingCards {
    Card c1, c2;  // c2: *DAMPING_PART_MASS's scale factors (FLAG = 1), else empty
    bool part = false;
  };
  std::vector<DampingCards> damping_cards;  // *DAMPING_GLOBAL, *DAMPING_PART_MASS
  std::vector<std::pair<Card, bool>> stiffness_damping_cards;  // *DAMPING_PART_STIFFNESS card, and whether _SET
  std::set<int> damped_parts;  // the parts *DAMPING_PART_STIFFNESS has given a value
  std::vector<std::pair<Card, Card>> fatigue_cards;  // *PCS_FATIGUE_PART: card 1, card 2 (or empty)
  Card body_parts_card;  // *LOAD_BODY_PARTS PSID
  bool has_body_parts = false;
  std::map<int, std::pair<int, double>> sections;         // secid → (elform, bar area)
  struct NodalRigidBodyCards {
    Card card;
    Eigen::Matrix<bool, 3, 1> fixed_translation{false, false, false}, fixed_rotation{false, false, false};
  };
  std::vector<NodalRigidBodyCards> rigid_cards;
  std::vector<Card> rigid_motion_cards;  // *BOUNDARY_PRESCRIBED_MOTION_RIGID
  std::vector<Card> discrete_cards, mass_cards, spc_cards, spc_set_cards, vel_cards, solid_cards,
      beam_cards, shell_cards, line_set_cards;
  std::vector<std::pair<Card, Card>> vel_set_cards, vel_gen_cards;
  std::map<int, RigidBody> inertias;  // *PART_INERTIA by part id
  std::map<int, std::vector<int>> solid_sets, shell_sets, beam_sets;  // element ids
  std::vector<Card> section_cards;
  std::map<int, std::pair<int, config::SourceLocation>> inertia_com_node;  // part id → NODEID
  struct SetUnion {
    bool parts = false;
    int id = 0;
    std::vector<int> members;
    config::SourceLocation where;
  };
  std::vector<SetUnion> set_unions;  // *SET_NODE_ADD, *SET_PART_ADD

  // Unions of sets, in deck order; a union of unions resolves once its members have.
  void resolve_set_unions() {
    std::vector<bool> done(set_unions.size(), false);
    for (size_t pass = 0; pass < set_unions.size(); ++pass)
      for (size_t i = 0; i < set_unions.size(); ++i) {
        if (done[i]) continue;
        const SetUnion& u = set_unions[i];
        auto& sets = u.parts ? m.part_sets : m.node_sets;
        bool ready = true;
        for (int id : u.members)
          for (size_t j = 0; j < set_unions.size(); ++j)
            if (!done[j] && j != i && set_unions[j].id == id && set_unions[j].parts == u.parts) ready = false;
        if (!ready) continue;
        std::vector<int> all;
        for (int id : u.members) {
          if (id == u.id) throw InputError(u.where, "set " + std::to_string(id) + " adds itself");
          auto it = sets.find(id);
          if (it == sets.end())
            throw InputError(u.where, std::string(u.parts ? "part" : "node") + " set " + std::to_string(id) + " is not defined");
          all.insert(all.end(), it->second.begin(), it->second.end());
        }
        std::sort(all.begin(), all.end());
        all.erase(std::unique(all.begin(), all.end()), all.end());
        sets[u.id] = all;
        done[i] = true;
      }
    for (size_t i = 0; i < set_unions.size(); ++i)
      if (!done[i]) throw InputError(set_unions[i].where, "set " + std::to_string(set_unions[i].id) + " is part of a cycle of *SET_..._ADD");
  }

  config::SourceLocation elout_where;  // the *DATABASE_ELOUT block, for its warning
  bool sort_tetrahedra = false;        // *CONTROL_SOLID ESORT 1: tetrahedra of ELFORM 1 parts run as ELFORM 10
  std::set<int> tet_in_hex_part;       // parts whose tetrahedra were said to be in an ELFORM 1 section

  static std::string short_number(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
  }

  void warn(const config::SourceLocation& w, const std::string& msg) {
    if (warnings) warnings->messages.push_back(w.str() + ": warning: " + msg);
  }

  // What the deck asks for, run as something else: refused by default, a
  // listed warning with --approximate.
  void substitute(const config::SourceLocation& w, const std::string& asked, const std::string& instead) {
    if (!warnings || !warnings->approximate)
      throw InputError(w, asked + " would run as " + instead +
                              ", which changes the result: fe_server --approximate runs it so, listing the substitution "
                              "in the log and in the results' attribute 'approximations'");
    warn(w, asked + " runs as " + instead + " (--approximate)");
    warnings->substitutions.push_back(w.str() + ": " + asked + " runs as " + instead);
  }

  // The penalty is capped at twice the default stiffness (contact.hpp says
  // why: beyond it central differences go unstable beside the elements' own
  // frequency). Said at start-up, not applied silently.
  void warn_stiffness_cap(const ContactDef& d, const char* name) {
    char value[32];
    std::snprintf(value, sizeof value, "%g", d.stiffness_factor);
    if (d.stiffness_factor > 2.0)
      warn(d.where, std::string(name) + " " + value +
                        " asks for a stiffer contact than central differences keep stable beside the elements' own "
                        "frequency: the penalty is capped at " + name + " 2 (0.2·m/Δt²)");
  }

  void block(const Block& b) {
    const std::string& kw = b.keyword;
    if (kw == "*KEYWORD" || kw == "*END" || kw == "*COMMENT") return;
    const auto& index = keyword_index();
    const auto it = index.find(kw);
    if (it == index.end()) return unsupported(b);
    (this->*(it->second->read))(b, kw);
  }

  // The keywords this reader reads: each with its reading function and what
  // it makes of it. The same table dispatches block() and prints the
  // coverage page (fe_server --keywords, docs/lsdyna_keywords.md).
  struct Keyword {
    std::vector<const char*> names;
    void (Reader::*read)(const Block&, const std::string&);
    const char* what;
  };
  static const std::vector<Keyword>& keywords() {
    static const std::vector<Keyword> k = {
      {{"*TITLE"}, &Reader::read_title, "the deck's title"},
      {{"*NODE"}, &Reader::read_node, "nodes: NID, X, Y, Z, TC"},
      {{"*PART"}, &Reader::read_part, "parts: title, PID, SECID, MID"},
      {{"*SECTION_SOLID"}, &Reader::read_section_solid, "solids' section: ELFORM 1 (one-point hexahedron), 10 (constant-strain tetrahedron)"},
      {{"*SECTION_BEAM"}, &Reader::read_section_beam, "1D bars' section (ELFORM, area)"},
      {{"*SECTION_SHELL"}, &Reader::read_section_shell, "2D axisymmetric solids' section (ELFORM)"},
      {{"*SECTION_DISCRETE"}, &Reader::read_section_discrete, "discrete springs' and dampers' section"},
      {{"*MAT_RIGID", "*MAT_020"}, &Reader::read_mat_rigid, "rigid material; its constraints and the body's mass properties"},
      {{"*PART_INERTIA"}, &Reader::read_part_inertia, "a part's given mass and inertia"},
      {{"*MAT_PLASTIC_KINEMATIC", "*MAT_003"}, &Reader::read_mat_plastic_kinematic, "elastic–plastic material, kinematic to isotropic hardening"},
      {{"*MAT_PIECEWISE_LINEAR_PLASTICITY", "*MAT_024"}, &Reader::read_mat_piecewise_linear_plasticity, "elastic–plastic material with a yield curve"},
      {{"*MAT_ELASTIC", "*MAT_001"}, &Reader::read_mat_elastic, "linear elastic material"},
      {{"*MAT_SPRING_ELASTIC", "*MAT_S01"}, &Reader::read_mat_spring_elastic, "linear spring"},
      {{"*MAT_DAMPER_VISCOUS", "*MAT_S02"}, &Reader::read_mat_damper_viscous, "linear damper"},
      {{"*ELEMENT_SOLID"}, &Reader::read_element_solid, "solid elements: hexahedra (wedges as degenerate ones), tetrahedra (4 nodes, or N4 repeated)"},
      {{"*ELEMENT_BEAM"}, &Reader::read_element_beam, "bar elements"},
      {{"*ELEMENT_SHELL"}, &Reader::read_element_shell, "axisymmetric 2D solid elements (4 nodes)"},
      {{"*ELEMENT_DISCRETE"}, &Reader::read_element_discrete, "discrete spring and damper elements"},
      {{"*ELEMENT_MASS"}, &Reader::read_element_mass, "lumped masses on nodes"},
      {{"*SET_NODE_LIST"}, &Reader::read_set_node_list, "node sets"},
      {{"*SET_NODE_LIST_GENERATE", "*SET_NODE_GENERATE"}, &Reader::read_set_node_generate, "node sets by ranges of ids"},
      {{"*SET_NODE_ADD", "*SET_PART_ADD"}, &Reader::read_set_node_add, "unions of node or part sets"},
      {{"*SET_PART_LIST", "*SET_PART"}, &Reader::read_set_part_list, "part sets"},
      {{"*SET_SOLID", "*SET_SOLID_LIST", "*SET_SHELL", "*SET_SHELL_LIST", "*SET_BEAM", "*SET_BEAM_LIST"}, &Reader::read_set_solid, "element sets"},
      {{"*DATABASE_CROSS_SECTION_SET"}, &Reader::read_database_cross_section_set, "cross sections for the section force output"},
      {{"*SET_SEGMENT"}, &Reader::read_set_segment, "segment sets"},
      {{"*CONSTRAINED_NODAL_RIGID_BODY", "*CONSTRAINED_NODAL_RIGID_BODY_SPC"}, &Reader::read_constrained_nodal_rigid_body, "nodal rigid bodies"},
      {{"*CONSTRAINED_EXTRA_NODES_NODE", "*CONSTRAINED_EXTRA_NODES_SET"}, &Reader::read_constrained_extra_nodes_node, "extra nodes on a rigid body"},
      {{"*CONSTRAINED_RIGID_BODIES"}, &Reader::read_constrained_rigid_bodies, "rigid bodies merged"},
      {{"*BOUNDARY_SPC_NODE"}, &Reader::read_boundary_spc_node, "single-point constraints on nodes"},
      {{"*BOUNDARY_SPC_SET"}, &Reader::read_boundary_spc_set, "single-point constraints on a node set"},
      {{"*INITIAL_VELOCITY_NODE"}, &Reader::read_initial_velocity_node, "initial velocities per node"},
      {{"*INITIAL_VELOCITY"}, &Reader::read_initial_velocity, "initial velocity of a node set"},
      {{"*INITIAL_VELOCITY_GENERATION"}, &Reader::read_initial_velocity_generation, "initial velocity (translation and rotation) of parts"},
      {{"*CONTACT_FORCE_TRANSDUCER_PENALTY"}, &Reader::read_contact_force_transducer_penalty, "a contact force transducer"},
      {{"*CONTACT_AUTOMATIC_SINGLE_SURFACE"}, &Reader::read_contact_automatic_single_surface, "single-surface penalty contact"},
      {{"*CONTACT_TIED_SURFACE_TO_SURFACE", "*CONTACT_TIED_NODES_TO_SURFACE"}, &Reader::read_contact_tied_surface_to_surface, "tied contact"},
      {{"*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", "*CONTACT_NODES_TO_SURFACE", "*CONTACT_AUTOMATIC_NODES_TO_SURFACE"}, &Reader::read_contact_automatic_surface_to_surface, "penalty surface-to-surface and nodes-to-surface contact"},
      {{"*USER_LOADING_SET"}, &Reader::read_user_loading_set, "the cavity ports the host's pressures load (the user-load hook)"},
      {{"*USER_LOADING_SQUEEZE_FILM"}, &Reader::read_user_loading_squeeze_film, "squeeze-film damping between two surfaces"},
      {{"*DEFINE_CURVE"}, &Reader::read_define_curve, "load curves"},
      {{"*LOAD_BODY_X", "*LOAD_BODY_Y", "*LOAD_BODY_Z"}, &Reader::read_load_body_x, "body accelerations along x, y or z"},
      {{"*DAMPING_GLOBAL"}, &Reader::read_damping_global, "mass-proportional damping of the whole model"},
      {{"*DAMPING_PART_MASS"}, &Reader::read_damping_part_mass, "mass-proportional damping of a part"},
      {{"*DAMPING_PART_STIFFNESS", "*DAMPING_PART_STIFFNESS_SET"}, &Reader::read_damping_part_stiffness, "stiffness-proportional (Rayleigh) damping of a part or part set, COEF < 0 (β)"},
      {{"*PCS_FATIGUE_PART"}, &Reader::read_pcs_fatigue_part, "our own card: the fatigue of a part's elements, counted during the run (S-N curve, mean-stress correction, notch factor)"},
      {{"*LOAD_NODE_POINT", "*LOAD_NODE_SET"}, &Reader::read_load_node_point, "point loads on nodes or node sets"},
      {{"*LOAD_SEGMENT", "*LOAD_SEGMENT_SET"}, &Reader::read_load_segment, "pressure loads on segments or segment sets"},
      {{"*LOAD_BODY_PARTS"}, &Reader::read_load_body_parts, "the parts a body load acts on"},
      {{"*CONTROL_DYNAMIC_RELAXATION"}, &Reader::read_control_dynamic_relaxation, "dynamic relaxation before the transient"},
      {{"*BOUNDARY_PRESCRIBED_MOTION_NODE", "*BOUNDARY_PRESCRIBED_MOTION_SET"}, &Reader::read_boundary_prescribed_motion_node, "prescribed motion of nodes or node sets"},
      {{"*BOUNDARY_PRESCRIBED_MOTION_RIGID"}, &Reader::read_boundary_prescribed_motion_rigid, "prescribed motion of a rigid body"},
      {{"*CONTROL_TERMINATION"}, &Reader::read_control_termination, "the end time"},
      {{"*CONTROL_TIMESTEP"}, &Reader::read_control_timestep, "the time step factor (TSSFAC) and mass scaling (DT2MS)"},
      {{"*CONTROL_HOURGLASS"}, &Reader::read_control_hourglass, "hourglass control (IHQ, QH)"},
      {{"*CONTROL_SOLID"}, &Reader::read_control_solid, "ESORT: tetrahedra of ELFORM 1 parts sorted to ELFORM 10"},
      {{"*CONTROL_BULK_VISCOSITY"}, &Reader::read_control_bulk_viscosity, "bulk viscosity (Q1, Q2)"},
      {{"*DATABASE_BINARY_D3PLOT"}, &Reader::read_database_binary_d3plot, "field snapshots (written as XDMF/HDF5 for ParaView)"},
      {{"*DATABASE_GLSTAT", "*DATABASE_RCFORC", "*DATABASE_NODOUT", "*DATABASE_ELOUT", "*DATABASE_SECFORC", "*DATABASE_MATSUM"}, &Reader::read_database_glstat, "ASCII outputs in LS-DYNA's formats as BINARY asks (2: the HDF5 history only), and the history's intervals"},
      {{"*DATABASE_HISTORY_NODE"}, &Reader::read_database_history_node, "nodal histories"},
      {{"*DATABASE_HISTORY_SOLID"}, &Reader::read_database_history_solid, "solid element histories"},
      {{"*DATABASE_HISTORY_BEAM"}, &Reader::read_database_history_beam, "bar element histories"},
      {{"*DATABASE_HISTORY_SHELL"}, &Reader::read_database_history_shell, "axisymmetric element histories"},
      {{"*CONTACT_2D_AUTOMATIC_SURFACE_TO_SURFACE"}, &Reader::read_contact_2d_automatic_surface_to_surface, "2D axisymmetric penalty contact"},
    };
    return k;
  }
  static const std::map<std::string, const Keyword*>& keyword_index() {
    static const std::map<std::string, const Keyword*> index = [] {
      std::map<std::string, const Keyword*> m;
      for (const Keyword& k : keywords())
        for (const char* n : k.names) m.emplace(n, &k);
      return m;
    }();
    return index;
  }

  // One function per keyword, in the order of the table.
  void read_title(const Block& b, [[maybe_unused]] const std::string& kw) {
    if (!b.cards.empty()) m.title = config::trim(b.cards[0].text);
  }

  void read_node(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) {
      Card c = fields_of(raw, {8, 16, 16, 16, 8, 8});
      int id = static_cast<int>(c.integer(0, "NID"));
      if (m.node_index.count(id)) c.fail("node " + std::to_string(id) + " defined twice");
      m.node_index[id] = static_cast<int>(m.node_ids.size());
      m.node_ids.push_back(id);
      m.x0.emplace_back(c.real_or(1, "X", 0), c.real_or(2, "Y", 0), c.real_or(3, "Z", 0));
      // TC as LS-DYNA numbers it (the CON1 code of rigid bodies too): 4 x
      // and y, 5 y and z, 6 z and x.
      m.fixed.push_back(constraint_code(c, 4, "TC"));
    }
  }

  void read_part(const Block& b, [[maybe_unused]] const std::string& kw) {
    if (b.cards.size() % 2) b.fail("*PART needs a title card and a PID card per part");
    for (size_t i = 0; i + 1 < b.cards.size(); i += 2) part(b.cards[i], b.cards[i + 1]);
  }

  void read_section_solid(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) {
      Card c = fields_of(raw, kW10);
      long elform = c.integer_or(1, "ELFORM", 1);
      if (elform == 0) elform = 1;
      if (elform == 13) {  // LS-DYNA's nodal-pressure tetrahedron
        substitute(c.where, "*SECTION_SOLID ELFORM 13", "ELFORM 10 (constant-strain tetrahedron, which locks where the "
                                                        "part is nearly incompressible or bends)");
        elform = 10;
      } else if (elform != 1 && elform != 10) {
        substitute(c.where, "*SECTION_SOLID ELFORM " + std::to_string(elform), "ELFORM 1 (one-point hexahedron)");
        elform = 1;
      }
      sections[static_cast<int>(c.integer(0, "SECID"))] = {static_cast<int>(elform), 0.0};
    }
  }

  void read_section_beam(const Block& b, [[maybe_unused]] const std::string& kw) {
    // Card 1: SECID, ELFORM (3 = truss); card 2 of a truss: A.
    for (size_t i = 0; i + 1 < b.cards.size(); i += 2) {
      Card c1 = fields_of(b.cards[i], kW10), c2 = fields_of(b.cards[i + 1], kW10);
      long elform = c1.integer_or(1, "ELFORM", 1);
      if (elform != 3) c1.fail("only truss beams (ELFORM 3, 1D bar) are supported");
      double area = c2.real(0, "A");
      if (!(area > 0.0)) c2.fail("truss area A must be positive");
      sections[static_cast<int>(c1.integer(0, "SECID"))] = {3, area};
    }
    if (b.cards.size() % 2) b.fail("*SECTION_BEAM needs two cards per section");
  }

  void read_section_shell(const Block& b, [[maybe_unused]] const std::string& kw) {
    // Card 1: SECID, ELFORM, ...; card 2: T1..T4, ... (not used by 2D solids).
    // ELFORM 15 (axisymmetric, volume weighted) is the element; 14 (area
    // weighted) runs as 15: both solve the same equations and converge to
    // the same answer, 15 conserves momentum and energy with the full-ring
    // loads that the cavity hook and contacts apply (element_axi4.hpp).
    for (size_t i = 0; i + 1 < b.cards.size(); i += 2) {
      Card c1 = fields_of(b.cards[i], kW10);
      const long elform = c1.integer_or(1, "ELFORM", 2);
      if (elform != 14 && elform != 15)
        c1.fail("ELFORM " + std::to_string(elform) +
                ": 3D shells are not modelled; this fe_server's shells are 2D axisymmetric solids only, ELFORM 15 "
                "(or 14): mesh a 3D part with solids (*ELEMENT_SOLID)");
      if (elform == 14)
        warn(c1.where, "ELFORM 14 (area weighted axisymmetric) runs as ELFORM 15 (volume weighted)");
      sections[static_cast<int>(c1.integer(0, "SECID"))] = {15, 0.0};
    }
    if (b.cards.size() % 2) b.fail("*SECTION_SHELL needs two cards per section");
  }

  void read_section_discrete(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) {
      Card c = fields_of(raw, kW10);
      if (c.fields.size() >= 2 && c.integer_or(1, "DRO", 0) != 0)
        c.fail("only translational discrete elements (DRO = 0) are supported");
    }
  }

  void read_mat_rigid(const Block& b, [[maybe_unused]] const std::string& kw) {
    // Card 1: MID RO E PR ...; card 2 (optional): CMO CON1 CON2; card 3
    // (optional): local axes for output, which change nothing here.
    if (b.cards.empty()) b.fail(kw + " needs its material card");
    Card c = fields_of(b.cards[0], kW10);
    Material mat = elastic_constants(c);
    mat.rigid = true;
    if (b.cards.size() >= 2) {
      Card c2 = fields_of(b.cards[1], kW10);
      const long cmo = static_cast<long>(c2.real_or(0, "CMO", 0.0));
      if (cmo == 1) {
        mat.rigid_fixed_translation = constraint_code(c2, 1, "CON1");
        mat.rigid_fixed_rotation = constraint_code(c2, 2, "CON2");
      } else if (cmo != 0) {
        c2.fail("CMO " + std::to_string(cmo) + ": only CMO = 0 (free) and 1 (global constraints CON1, CON2) are supported");
      }
    }
    if (b.cards.size() > 3) b.fail(kw + " has at most three cards; define each material under its own keyword");
    if (m.materials.count(mat.id)) c.fail("material " + std::to_string(mat.id) + " defined twice");
    m.materials[mat.id] = mat;
  }

  void read_part_inertia(const Block& b, [[maybe_unused]] const std::string& kw) {
    part_inertia(b);
  }

  void read_mat_plastic_kinematic(const Block& b, [[maybe_unused]] const std::string& kw) {
    // MID RO E PR SIGY ETAN BETA; card 2: SRC SRP FS VP.
    if (b.cards.empty()) b.fail(kw + " needs its material card");
    Card c = fields_of(b.cards[0], kW10);
    Material mat = elastic_constants(c);
    plastic_constants(mat, c);
    mat.beta = c.real_or(6, "BETA", 0.0);
    if (mat.beta < 0.0 || mat.beta > 1.0) c.fail("BETA must be between 0 (kinematic) and 1 (isotropic)");
    if (b.cards.size() > 1) {
      Card c2 = fields_of(b.cards[1], kW10);
      if (c2.real_or(0, "SRC", 0.0) != 0.0 || c2.real_or(1, "SRP", 0.0) != 0.0)
        c2.fail("strain-rate effects (SRC, SRP) are not supported");
      if (c2.real_or(2, "FS", 0.0) != 0.0) c2.fail("failure (FS, element erosion) is not supported");
    }
    if (b.cards.size() > 2) b.fail(kw + " has at most two cards; define each material under its own keyword");
    if (m.materials.count(mat.id)) c.fail("material " + std::to_string(mat.id) + " defined twice");
    m.materials[mat.id] = mat;
  }

  void read_mat_piecewise_linear_plasticity(const Block& b, [[maybe_unused]] const std::string& kw) {
    // MID RO E PR SIGY ETAN FAIL TDEL; C P LCSS LCSR VP; EPS1..8; ES1..8.
    if (b.cards.empty()) b.fail(kw + " needs its material card");
    Card c = fields_of(b.cards[0], kW10);
    Material mat = elastic_constants(c);
    plastic_constants(mat, c);
    const double fail = c.real_or(6, "FAIL", 0.0);
    if (fail != 0.0 && fail < 1e20) c.fail("failure (FAIL, element erosion) is not supported");
    if (b.cards.size() > 1) {
      Card c2 = fields_of(b.cards[1], kW10);
      if (c2.real_or(0, "C", 0.0) != 0.0 || c2.real_or(1, "P", 0.0) != 0.0)
        c2.fail("strain-rate effects (C, P) are not supported");
      if (c2.integer_or(3, "LCSR", 0) != 0) c2.fail("LCSR (a strain-rate curve) is not supported");
      if (const long lcss = c2.integer_or(2, "LCSS", 0); lcss != 0) hardening_curves.push_back({mat.id, c2});
    }
    if (b.cards.size() > 3) {
      Card eps = fields_of(b.cards[2], kW10), es = fields_of(b.cards[3], kW10);
      // Cards of zeros are no curve: LS-DYNA then takes SIGY and ETAN (or
      // LCSS), and LS-PrePost writes them so. Strains without stresses are
      // a mistake, not a curve.
      bool no_stress = true, no_strain = true;
      for (size_t k = 0; k < 8; ++k) {
        no_stress = no_stress && es.real_or(k, "ES", 0.0) == 0.0;
        no_strain = no_strain && eps.real_or(k, "EPS", 0.0) == 0.0;
      }
      if (no_stress && !no_strain) es.fail("EPS are given but every ES is 0: give the yield stresses, or zeros in both cards for SIGY and ETAN");
      for (size_t k = 0; k < 8 && !no_stress; ++k) {
        const double e = eps.real_or(k, "EPS", 0.0), sy = es.real_or(k, "ES", 0.0);
        if (sy == 0.0 && k > 0) break;
        if (!mat.hardening_strain.empty() && !(e > mat.hardening_strain.back()))
          eps.fail("EPS must increase");
        mat.hardening_strain.push_back(e);
        mat.hardening_stress.push_back(sy);
      }
      if (mat.hardening_strain.size() == 1) es.fail("EPS/ES need at least two points");
    }
    if (b.cards.size() > 4) b.fail(kw + " has at most four cards; define each material under its own keyword");
    if (m.materials.count(mat.id)) c.fail("material " + std::to_string(mat.id) + " defined twice");
    m.materials[mat.id] = mat;
  }

  void read_mat_elastic(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) {
      Card c = fields_of(raw, kW10);
      if (c.fields.empty() || c.fields[0].empty()) continue;
      Material mat = elastic_constants(c);
      if (m.materials.count(mat.id)) c.fail("material " + std::to_string(mat.id) + " defined twice");
      m.materials[mat.id] = mat;
    }
  }

  void read_mat_spring_elastic(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) {
      Card c = fields_of(raw, kW10);
      spring_mats[static_cast<int>(c.integer(0, "MID"))].first = c.real(1, "K");
    }
  }

  void read_mat_damper_viscous(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) {
      Card c = fields_of(raw, kW10);
      spring_mats[static_cast<int>(c.integer(0, "MID"))].second = c.real(1, "DC");
    }
  }

  void read_element_solid(const Block& b, [[maybe_unused]] const std::string& kw) {
    // One card (EID PID N1..N8), or LS-DYNA's two-card form: EID PID, then
    // the nodes on the next card (N1..N8, or N1..N10 for a 10-node tet).
    for (size_t i = 0; i < b.cards.size(); ++i) {
      Card c = fields_of(b.cards[i], kW8);
      const auto filled = std::count_if(c.fields.begin(), c.fields.end(), [](const std::string& f) { return !f.empty(); });
      if (filled <= 2) {
        if (i + 1 == b.cards.size()) c.fail("element " + (c.fields.empty() ? std::string("card") : c.fields[0]) +
                                            ": the two-card form needs the nodes on the next card");
        const Card nodes = fields_of(b.cards[++i], kW8);
        c.fields.resize(2);
        c.fields.insert(c.fields.end(), nodes.fields.begin(), nodes.fields.end());
      }
      solid_cards.push_back(c);
    }
  }

  void read_element_beam(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) beam_cards.push_back(fields_of(raw, kW8));
  }

  void read_element_shell(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) shell_cards.push_back(fields_of(raw, kW8));
  }

  void read_element_discrete(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) discrete_cards.push_back(fields_of(raw, {8, 8, 8, 8, 8, 16, 8, 16}));
  }

  void read_element_mass(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) mass_cards.push_back(fields_of(raw, {8, 8, 16, 8}));
  }

  void read_set_node_list(const Block& b, [[maybe_unused]] const std::string& kw) {
    if (b.cards.empty()) b.fail("*SET_NODE_LIST needs a header card with SID");
    auto& list = m.node_sets[static_cast<int>(fields_of(b.cards[0], kW10).integer(0, "SID"))];
    for (int id : id_list(b, 1, "NID")) list.push_back(id);
  }

  void read_set_node_generate(const Block& b, [[maybe_unused]] const std::string& kw) {
    // SID, then ranges B1 E1 B2 E2 ...: every defined node with an id in a range.
    if (b.cards.empty()) b.fail(kw + " needs a header card with SID");
    auto& list = m.node_sets[static_cast<int>(fields_of(b.cards[0], kW10).integer(0, "SID"))];
    for (size_t i = 1; i < b.cards.size(); ++i) {
      Card c = fields_of(b.cards[i], kW10);
      for (size_t k = 0; k + 1 < c.fields.size(); k += 2) {
        if (c.fields[k].empty() && c.fields[k + 1].empty()) continue;
        const long lo = c.integer(k, "B"), hi = c.integer(k + 1, "E");
        if (hi < lo) c.fail("range " + std::to_string(lo) + " to " + std::to_string(hi) + " is empty");
        for (auto it = m.node_index.lower_bound(static_cast<int>(lo)); it != m.node_index.end() && it->first <= hi; ++it)
          list.push_back(it->first);
      }
    }
  }

  void read_set_node_add(const Block& b, [[maybe_unused]] const std::string& kw) {
    // SID, then the ids of the sets it joins (resolved after the deck is read).
    if (b.cards.empty()) b.fail(kw + " needs a header card with SID");
    SetUnion u;
    u.parts = kw == "*SET_PART_ADD";
    u.id = static_cast<int>(fields_of(b.cards[0], kW10).integer(0, "SID"));
    u.members = id_list(b, 1, "DSID");
    u.where = b.where;
    set_unions.push_back(u);
    (u.parts ? m.part_sets : m.node_sets)[u.id];  // defined from here on
  }

  void read_set_part_list(const Block& b, [[maybe_unused]] const std::string& kw) {
    if (b.cards.empty()) b.fail(kw + " needs a header card with SID");
    auto& list = m.part_sets[static_cast<int>(fields_of(b.cards[0], kW10).integer(0, "SID"))];
    for (int id : id_list(b, 1, "PID")) list.push_back(id);
  }

  void read_set_solid(const Block& b, [[maybe_unused]] const std::string& kw) {
    if (b.cards.empty()) b.fail(kw + " needs a header card with SID");
    auto& sets = kw.rfind("*SET_SOLID", 0) == 0 ? solid_sets : kw.rfind("*SET_SHELL", 0) == 0 ? shell_sets : beam_sets;
    auto& list = sets[static_cast<int>(fields_of(b.cards[0], kW10).integer(0, "SID"))];
    for (int id : id_list(b, 1, "EID")) list.push_back(id);
  }

  void read_database_cross_section_set(const Block& b, [[maybe_unused]] const std::string& kw) {
    // NSID HSID BSID SSID TSID DSID ID ITYPE: the cut's nodes and the
    // solid, beam and shell (here: axisymmetric) elements on one side.
    for (const Card& raw : b.cards) section_cards.push_back(fields_of(raw, kW10));
  }

  void read_set_segment(const Block& b, [[maybe_unused]] const std::string& kw) {
    if (b.cards.empty()) b.fail("*SET_SEGMENT needs a header card with SID");
    auto& list = m.segment_sets[static_cast<int>(fields_of(b.cards[0], kW10).integer(0, "SID"))];
    for (size_t i = 1; i < b.cards.size(); ++i) {
      Card c = fields_of(b.cards[i], kW10);
      Segment s;
      const long n3 = c.integer_or(2, "N3", 0), n4 = c.integer_or(3, "N4", 0);
      if (n3 == 0 && n4 == 0) {  // N1, N2 only: a 2D line (axisymmetric decks), body on its left
        s.n[0] = m.index_of(static_cast<int>(c.integer(0, "N1")), c.where);
        s.n[1] = m.index_of(static_cast<int>(c.integer(1, "N2")), c.where);
        s.n[2] = s.n[3] = -1;
        line_set_cards.push_back(c);
      } else {
        for (int k = 0; k < 4; ++k) {
          long id = c.integer_or(static_cast<size_t>(k), "N", k == 3 ? 0 : -1);
          if (k == 3 && id == 0) {
            s.n[3] = s.n[2];  // triangle
            continue;
          }
          s.n[k] = m.index_of(static_cast<int>(id), c.where);
        }
      }
      list.push_back(s);
    }
  }

  void read_constrained_nodal_rigid_body(const Block& b, [[maybe_unused]] const std::string& kw) {
    // _SPC: each body's card is followed by CMO CON1 CON2 (as *MAT_RIGID's).
    const bool spc = kw == "*CONSTRAINED_NODAL_RIGID_BODY_SPC";
    if (spc && b.cards.size() % 2) b.fail(kw + " needs two cards per body (PID CID NSID; CMO CON1 CON2)");
    for (size_t i = 0; i < b.cards.size(); i += spc ? 2 : 1) {
      // Not `{card, {}, {}}`: an explicit {} would replace the members'
      // initialisers with Eigen's default constructor, which leaves them unset.
      NodalRigidBodyCards r;
      r.card = fields_of(b.cards[i], kW10);
      if (spc) {
        Card c2 = fields_of(b.cards[i + 1], kW10);
        const long cmo = static_cast<long>(c2.real_or(0, "CMO", 0.0));
        if (cmo != 0 && cmo != 1) c2.fail("CMO " + std::to_string(cmo) + ": only 0 (free) and 1 (global CON1, CON2) are supported");
        if (cmo == 1) {
          r.fixed_translation = constraint_code(c2, 1, "CON1");
          r.fixed_rotation = constraint_code(c2, 2, "CON2");
        }
      }
      rigid_cards.push_back(r);
    }
  }

  void read_constrained_extra_nodes_node(const Block& b, [[maybe_unused]] const std::string& kw) {
    // PID, NID (or NSID): the nodes move with the rigid part PID.
    for (const Card& raw : b.cards) extra_node_cards.push_back({fields_of(raw, kW10), kw == "*CONSTRAINED_EXTRA_NODES_SET"});
  }

  void read_constrained_rigid_bodies(const Block& b, [[maybe_unused]] const std::string& kw) {
    // PIDL, PIDC, IFLAG: rigid part PIDC joins the lead part PIDL's body.
    for (const Card& raw : b.cards) merge_cards.push_back(fields_of(raw, kW10));
  }

  void read_boundary_spc_node(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) spc_cards.push_back(fields_of(raw, kW10));
  }

  void read_boundary_spc_set(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) spc_set_cards.push_back(fields_of(raw, kW10));
  }

  void read_initial_velocity_node(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) vel_cards.push_back(fields_of(raw, kW10));
  }

  void read_initial_velocity(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (size_t i = 0; i + 1 < b.cards.size(); i += 2)
      vel_set_cards.push_back({fields_of(b.cards[i], kW10), fields_of(b.cards[i + 1], kW10)});
    if (b.cards.size() % 2) b.fail("*INITIAL_VELOCITY needs two cards per set");
  }

  void read_initial_velocity_generation(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (size_t i = 0; i + 1 < b.cards.size(); i += 2)
      vel_gen_cards.push_back({fields_of(b.cards[i], kW10), fields_of(b.cards[i + 1], kW10)});
    if (b.cards.size() % 2) b.fail("*INITIAL_VELOCITY_GENERATION needs two cards per entry");
  }

  void read_contact_force_transducer_penalty(const Block& b, [[maybe_unused]] const std::string& kw) {
    // Measures the contact force on its surfaces and applies none: output only.
    warn(b.where, kw + " only measures contact forces for LS-DYNA's rcforc file: ignored (fe_server writes the "
                       "contacts' total force in contact/force)");
  }

  void read_contact_automatic_single_surface(const Block& b, [[maybe_unused]] const std::string& kw) {
    // Card 1: SSID, MSID (not used), SSTYP (2: part set, 3: part; SSID 0:
    // every part), MSTYP; card 2: FS FD DC VC VDC; card 3: SFS.
    ContactDef d;
    Card c1 = b.cards.empty() ? Card{} : fields_of(b.cards[0], kW10);
    d.where = b.cards.empty() ? b.where : c1.where;
    d.single_surface = true;
    const long ssid = b.cards.empty() ? 0 : c1.integer_or(0, "SSID", 0);
    const long sstyp = b.cards.empty() ? 2 : c1.integer_or(2, "SSTYP", 2);
    if (ssid != 0 && sstyp != 2 && sstyp != 3)
      c1.fail("SSTYP must be 2 (part set) or 3 (part) for a single surface in this version (SSID 0: all parts)");
    d.slave_set = static_cast<int>(ssid);
    d.slave_nodes = sstyp == 3;  // read here as: SSID names one part (resolved after the deck)
    contact_cards_2_and_3(b, d);
    m.contacts.push_back(d);
  }

  void read_contact_tied_surface_to_surface(const Block& b, [[maybe_unused]] const std::string& kw) {
    // Card 1: SSID MSID SSTYP MSTYP (segment sets, or a slave node set:
    // SSTYP 4, the default of _NODES_TO_SURFACE); cards 2 and 3 (friction,
    // damping, SFS, thicknesses) mean nothing for a constraint and are read
    // as LS-DYNA does: not used.
    TieDef d;
    contact_card_1(b, kw == "*CONTACT_TIED_NODES_TO_SURFACE", d.slave_set, d.master_set, d.slave_nodes, d.where);
    m.ties.push_back(d);
  }

  void read_contact_automatic_surface_to_surface(const Block& b, [[maybe_unused]] const std::string& kw) {
    // _NODES_TO_SURFACE: the slave side is a node set unless SSTYP says
    // otherwise, checked against the master's segments only (one-sided).
    const bool nodes_to_surface = kw != "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE";
    ContactDef d;
    contact_card_1(b, nodes_to_surface, d.slave_set, d.master_set, d.slave_nodes, d.where);
    if (nodes_to_surface && !d.slave_nodes) throw InputError(d.where, kw + ": the slave side must be a node set (SSTYP 4)");
    contact_cards_2_and_3(b, d);
    m.contacts.push_back(d);
  }

  void read_user_loading_set(const Block& b, [[maybe_unused]] const std::string& kw) {
    // Co-simulation port on a segment set: SID, LTYPE (PRESSS), PORT, and
    // optionally the cavity's bounds along z: ZMIN, ZMAX, REFNODE (the bounds
    // move with this node, e.g. on the housing), RAMP (entry width of faces
    // normal to z).
    for (const Card& raw : b.cards) {
      Card c = fields_of(raw, kW10);
      LoadingSet ls;
      ls.segment_set = static_cast<int>(c.integer(0, "SID"));
      std::string ltype = config::to_upper(c.field(1, "LTYPE"));
      if (ltype != "PRESSS" && ltype != "FORCE" && ltype != "BODY")
        c.fail("LTYPE '" + c.fields[1] +
               "': expected PRESSS (pressure on a segment set), FORCE (force along the axis on a node set) or BODY "
               "(force along the axis on a part set, shared by mass)");
      ls.force = ltype == "FORCE" || ltype == "BODY";
      ls.body = ltype == "BODY";
      ls.port_id = static_cast<int>(c.integer(2, "PORT"));
      ls.z_min = c.real_or(3, "ZMIN", -1e300);
      ls.z_max = c.real_or(4, "ZMAX", 1e300);
      const long ref = c.integer_or(5, "REFNODE", 0);
      ls.reference_node = ref ? m.index_of(static_cast<int>(ref), c.where) : -1;
      ls.ramp = c.real_or(6, "RAMP", 0.0);
      if (!(ls.z_min < ls.z_max)) c.fail("ZMIN must be below ZMAX");
      ls.where = c.where;
      m.loading_sets.push_back(ls);
    }
  }

  void read_user_loading_squeeze_film(const Block& b, [[maybe_unused]] const std::string& kw) {
    // NSID1 NSID2 DIR H0 RO RI MU HMIN, one film per card.
    for (const Card& raw : b.cards) {
      Card c = fields_of(raw, kW10);
      SqueezeFilmDef f;
      f.where = c.where;
      f.set1 = static_cast<int>(c.integer(0, "NSID1"));
      f.set2 = static_cast<int>(c.integer(1, "NSID2"));
      f.direction = c.real(2, "DIR");
      if (f.direction != 1.0 && f.direction != -1.0)
        c.fail("DIR must be 1 (the gap grows as NSID1 moves along +axis relative to NSID2) or -1");
      f.h0 = c.real(3, "H0");
      f.r_out = c.real(4, "RO");
      f.r_in = c.real_or(5, "RI", 0.0);
      f.viscosity = c.real(6, "MU");
      f.h_min = c.real_or(7, "HMIN", 5e-6);
      if (!(f.r_out > 0.0) || !(f.r_in >= 0.0) || !(f.r_in < f.r_out)) c.fail("the film needs 0 <= RI < RO");
      if (!(f.viscosity > 0.0)) c.fail("MU (the oil's dynamic viscosity, Pa s) must be positive");
      if (!(f.h_min > 0.0)) c.fail("HMIN must be positive (the gap below which the film's coefficient is held)");
      if (f.set1 == f.set2) c.fail("NSID1 and NSID2 are the same set: the film needs two faces");
      m.squeeze_films.push_back(f);
    }
  }

  void read_define_curve(const Block& b, [[maybe_unused]] const std::string& kw) {
    // LCID SIDR SFA SFO OFFA OFFO DATTYP, then one point (A, O) per card (2 fields of 20).
    if (b.cards.empty()) b.fail("*DEFINE_CURVE needs a card with LCID");
    Card c = fields_of(b.cards[0], kW10);
    Curve curve;
    curve.id = static_cast<int>(c.integer(0, "LCID"));
    curve.where = c.where;
    const long sidr = c.integer_or(1, "SIDR", 0);
    if (sidr < 0 || sidr > 2) c.fail("SIDR " + std::to_string(sidr) + ": 0 (transient), 1 (dynamic relaxation) or 2 (both)");
    curve.sidr = static_cast<int>(sidr);
    curve.sfa = c.real_or(2, "SFA", 0.0);
    curve.sfo = c.real_or(3, "SFO", 0.0);
    if (curve.sfa == 0.0) curve.sfa = 1.0;  // LS-DYNA: 0 means 1
    if (curve.sfo == 0.0) curve.sfo = 1.0;
    curve.offa = c.real_or(4, "OFFA", 0.0);
    curve.offo = c.real_or(5, "OFFO", 0.0);
    if (c.integer_or(6, "DATTYP", 0) != 0) c.fail("DATTYP other than 0 (a time curve) is not supported");
    for (size_t i = 1; i < b.cards.size(); ++i) {
      Card pt = fields_of(b.cards[i], {20});
      const double a = pt.real(0, "A1"), o = pt.real_or(1, "O1", 0.0);
      if (!curve.a.empty() && !(a > curve.a.back()))
        pt.fail("the curve's abscissae must increase (" + std::to_string(a) + " after " + std::to_string(curve.a.back()) + ")");
      curve.a.push_back(a);
      curve.o.push_back(o);
    }
    if (curve.a.empty()) c.fail("curve " + std::to_string(curve.id) + " has no points");
    if (m.curves.count(curve.id)) c.fail("curve " + std::to_string(curve.id) + " defined twice");
    m.curves[curve.id] = curve;
  }

  void read_load_body_x(const Block& b, [[maybe_unused]] const std::string& kw) {
    // LCID SF LCIDDR XC YC ZC CID
    if (b.cards.empty()) b.fail(kw + " needs a card with LCID");
    Card c = fields_of(b.cards[0], kW10);
    BodyLoad l;
    l.dof = kw.back() - 'X';
    l.curve_id = static_cast<int>(c.integer(0, "LCID"));
    l.sf = c.real_or(1, "SF", 1.0);
    if (l.sf == 0.0) l.sf = 1.0;  // LS-DYNA: 0 means 1
    l.curve_dr_id = static_cast<int>(c.integer_or(2, "LCIDDR", 0));
    if (c.integer_or(6, "CID", 0) != 0) c.fail("CID (a local coordinate system) is not supported");
    l.where = c.where;
    m.body_loads.push_back(l);
  }

  void read_damping_global(const Block& b, [[maybe_unused]] const std::string& kw) {
    // LCID VALDMP STX STY STZ SRX SRY SRZ
    if (b.cards.empty()) return;  // LS-DYNA's defaults: no damping
    damping_cards.push_back({fields_of(b.cards[0], kW10), Card{}, false});
  }

  void read_damping_part_mass(const Block& b, [[maybe_unused]] const std::string& kw) {
    // PID LCID SF FLAG, and with FLAG = 1 a card STX STY STZ SRX SRY SRZ.
    for (size_t i = 0; i < b.cards.size(); ++i) {
      Card c1 = fields_of(b.cards[i], kW10);
      Card c2;
      if (c1.integer_or(3, "FLAG", 0) == 1) {
        if (i + 1 == b.cards.size()) c1.fail("FLAG = 1 needs the card of scale factors STX ... SRZ");
        c2 = fields_of(b.cards[++i], kW10);
      }
      damping_cards.push_back({c1, c2, true});
    }
  }

  void read_damping_part_stiffness(const Block& b, const std::string& kw) {
    // PID (or PSID) COEF, a card per part or set.
    for (const Card& card : b.cards) stiffness_damping_cards.push_back({fields_of(card, kW10), kw == "*DAMPING_PART_STIFFNESS_SET"});
  }

  // COEF < 0 is the classical Rayleigh stiffness damping C = β·K with
  // β = |COEF| (LS-DYNA's 950 formulation, which later versions keep for a
  // negative COEF). COEF > 0 is LS-DYNA's own high-frequency formulation
  // ("an approximate fraction of critical damping"), whose details LSTC do
  // not publish: running it as β would be a different damping under the
  // same number, so it is refused with what to give instead.
  void stiffness_damping(const Card& c, bool is_set) {
    const double coef = c.real(1, "COEF");
    if (coef > 0.0)
      c.fail("COEF " + c.fields.at(1) + " > 0 asks for LS-DYNA's proprietary high-frequency stiffness damping, which "
             "is not reproduced; give COEF = -beta, the Rayleigh coefficient of C = beta*K in s, with beta = "
             "2*zeta/omega for the fraction zeta of critical damping at the angular frequency omega you mean "
             "(0.5 % at 4 kHz: COEF = -3.98e-7)");
    if (!std::isfinite(coef)) c.fail("COEF must be a finite number");
    std::vector<int> pids;
    if (is_set) {
      const long psid = c.integer(0, "PSID");
      auto it = m.part_sets.find(static_cast<int>(psid));
      if (it == m.part_sets.end()) c.fail("part set " + std::to_string(psid) + " is not defined");
      pids.assign(it->second.begin(), it->second.end());
    } else {
      pids.push_back(static_cast<int>(c.integer(0, "PID")));
    }
    for (const int pid : pids) {
      auto part = m.parts.find(pid);
      if (part == m.parts.end()) c.fail("PID " + std::to_string(pid) + " is not a *PART");
      if (std::any_of(m.bars.begin(), m.bars.end(), [&](const BarElement& e) { return e.part == pid; }))
        c.fail("part " + std::to_string(pid) + " holds bar elements: stiffness damping is applied by the solid and "
               "axisymmetric elements only (damp a bar with a *MAT_SPRING_ELASTIC's damper beside it)");
      if (std::none_of(m.solids.begin(), m.solids.end(), [&](const SolidElement& e) { return e.part == pid; }) &&
          std::none_of(m.axis.begin(), m.axis.end(), [&](const AxiElement& e) { return e.part == pid; }))
        c.fail("part " + std::to_string(pid) + " has no solid or axisymmetric elements: stiffness damping would do "
               "nothing there");
      if (m.materials.at(part->second.material).rigid)
        c.fail("part " + std::to_string(pid) + " is rigid: stiffness damping acts on deformation, which a rigid body has none of");
      if (!damped_parts.insert(pid).second)
        c.fail("part " + std::to_string(pid) + " is given stiffness damping twice: one value per part");
      part->second.stiffness_damping = -coef;
    }
  }

  void read_pcs_fatigue_part(const Block& b, [[maybe_unused]] const std::string& kw) {
    // Two cards per part: PID SA_REF N_REF M SE HAIBACH STRESS MEAN, then SU KF GATE DT.
    if (b.cards.empty() || b.cards.size() % 2 != 0)
      b.fail("*PCS_FATIGUE_PART takes two cards per part (PID SA_REF N_REF M SE HAIBACH STRESS MEAN, then SU KF "
             "GATE: 0,1,0 for none, a notch factor of 1, no gate); it has " + std::to_string(b.cards.size()));
    for (size_t i = 0; i < b.cards.size(); i += 2)
      fatigue_cards.push_back({fields_of(b.cards[i], kW10), fields_of(b.cards[i + 1], kW10)});
  }

  void fatigue_part(const Card& c, const Card& c2) {
    FatigueDef f;
    f.where = c.where;
    const long pid = c.integer(0, "PID");
    auto part = m.parts.find(static_cast<int>(pid));
    if (part == m.parts.end()) c.fail("PID " + std::to_string(pid) + " is not a *PART");
    if (m.materials.at(part->second.material).rigid) c.fail("part " + std::to_string(pid) + " is rigid: it has no stress");
    f.part = static_cast<int>(pid);
    f.curve.sa_ref = c.real(1, "SA_REF");
    f.curve.n_ref = c.real(2, "N_REF");
    f.curve.m = c.real(3, "M");
    f.curve.endurance = c.real_or(4, "SE", 0.0);
    f.curve.haibach = c.integer_or(5, "HAIBACH", 0) != 0;
    if (const std::string why = f.curve.check(); !why.empty()) c.fail("S-N curve: " + why);
    // The elements counted are the part's solids, or in an axisymmetric deck
    // its axisymmetric ones (output/fatigue.hpp): a part of bars or springs
    // would count nothing, and the run end with no word of it.
    const bool axisymmetric = m.solids.empty() && !m.axis.empty();
    const auto of_part = [&](const auto& elements) {
      return std::count_if(elements.begin(), elements.end(), [&](const auto& e) { return e.part == pid; });
    };
    if ((axisymmetric ? of_part(m.axis) : of_part(m.solids)) == 0)
      c.fail("part " + std::to_string(pid) + " has no " + (axisymmetric ? "axisymmetric" : "solid") +
             " elements: fatigue is counted on those only, not on bars, springs or masses");
    // The curve in the deck's stress unit: a fatigue strength is 1e-4 to 1e-2
    // of E (steels 200-800 MPa at 210 GPa, aluminium 50-150 MPa at 70 GPa).
    // Far outside, it is in another unit (MPa in a Pa deck), which would
    // count no damage, or all of it, and end with exit 0.
    const double E = m.materials.at(part->second.material).E;
    auto plausible = [&](double stress, const char* name, const Card& card) {
      if (E > 0.0 && stress > 0.0 && (stress < 1e-5 * E || stress > 0.1 * E)) {
        char why[240];
        std::snprintf(why, sizeof why, "%s %g is %.3g of the part's E (%g): a metal's fatigue strength is 1e-4 to "
                      "1e-2 of E; is it in the deck's stress unit?", name, stress, stress / E, E);
        card.fail(why);
      }
    };
    plausible(f.curve.sa_ref, "SA_REF", c);
    plausible(f.curve.endurance, "SE", c);
    f.stress = static_cast<int>(c.integer_or(6, "STRESS", 0));
    if (f.stress != 0 && f.stress != 1) c.fail("STRESS " + std::to_string(f.stress) + ": 0 (signed von Mises) or 1 (largest principal)");
    const long mean = c.integer_or(7, "MEAN", 0);
    if (mean < 0 || mean > 3) c.fail("MEAN " + std::to_string(mean) + ": 0 none, 1 Goodman, 2 Gerber, 3 SWT");
    f.mean = static_cast<fatigue::MeanStress>(mean);
    f.su = c2.real_or(0, "SU", 0.0);
    f.kf = c2.real_or(1, "KF", 1.0);
    f.gate = c2.real_or(2, "GATE", 0.0);
    f.dt = c2.real_or(3, "DT", 0.0);
    if (!(f.dt >= 0.0)) c2.fail("DT must be 0 (every FE step) or more");
    if ((f.mean == fatigue::MeanStress::Goodman || f.mean == fatigue::MeanStress::Gerber) && !(f.su > 0.0))
      c2.fail("MEAN " + std::to_string(mean) + " needs SU, the ultimate strength, on card 2");
    plausible(f.su, "SU", c2);
    if (!(f.kf >= 1.0)) c2.fail("KF must be 1 or more (a notch raises the stress)");
    if (!(f.gate >= 0.0)) c2.fail("GATE must be 0 or more");
    for (const FatigueDef& other : m.fatigue)
      if (other.part == f.part) c.fail("part " + std::to_string(pid) + " has a *PCS_FATIGUE_PART already, at " + other.where.str());
    m.fatigue.push_back(f);
  }

  void read_load_node_point(const Block& b, [[maybe_unused]] const std::string& kw) {
    // NID (or NSID), DOF, LCID, SF, CID, M1, M2, M3.
    for (const Card& raw : b.cards) nodal_load_cards.push_back({fields_of(raw, kW10), kw == "*LOAD_NODE_SET"});
  }

  void read_load_segment(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) pressure_cards.push_back({fields_of(raw, kW10), kw == "*LOAD_SEGMENT_SET"});
  }

  void read_load_body_parts(const Block& b, [[maybe_unused]] const std::string& kw) {
    if (b.cards.empty()) b.fail("*LOAD_BODY_PARTS needs a card with PSID");
    body_parts_card = fields_of(b.cards[0], kW10);
    has_body_parts = true;
  }

  void read_control_dynamic_relaxation(const Block& b, [[maybe_unused]] const std::string& kw) {
    // NRCYCK DRTOL DRFCTR DRTERM TSSFDR IRELAL EDTTL IDRFLG
    Card c = b.cards.empty() ? Card{} : fields_of(b.cards[0], kW10);
    auto& r = m.relaxation;
    r.where = b.where;
    if (!b.cards.empty()) {
      r.nrcyck = static_cast<int>(c.integer_or(0, "NRCYCK", 0));
      if (r.nrcyck == 0) r.nrcyck = 250;
      r.drtol = c.real_or(1, "DRTOL", 0.0);
      if (r.drtol == 0.0) r.drtol = 1e-3;
      r.drfctr = c.real_or(2, "DRFCTR", 0.0);
      if (r.drfctr == 0.0) r.drfctr = 0.995;
      r.drterm = c.real_or(3, "DRTERM", 0.0);
      if (r.drterm == 0.0) r.drterm = 1e28;
      if (c.real_or(4, "TSSFDR", 0.0) != 0.0) c.fail("TSSFDR (another step for the relaxation) is not supported: leave it 0");
      r.idrflg = c.integer_or(7, "IDRFLG", 0) == 1;
      if (r.nrcyck < 1 || !(r.drtol > 0.0 && r.drtol < 1.0) || !(r.drfctr > 0.0 && r.drfctr < 1.0) || !(r.drterm > 0.0))
        c.fail("NRCYCK ≥ 1, 0 < DRTOL < 1, 0 < DRFCTR < 1 and DRTERM > 0 are needed");
    }
  }

  void read_boundary_prescribed_motion_node(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (const Card& raw : b.cards) motion_cards.push_back({fields_of(raw, kW10), kw == "*BOUNDARY_PRESCRIBED_MOTION_SET"});
  }

  void read_boundary_prescribed_motion_rigid(const Block& b, [[maybe_unused]] const std::string& kw) {
    // PID DOF VAD LCID SF VID DEATH BIRTH: the part's rigid body translates
    // as the curve says (resolved after the deck: the part's body).
    for (const Card& raw : b.cards) rigid_motion_cards.push_back(fields_of(raw, kW10));
  }

  void read_control_termination(const Block& b, [[maybe_unused]] const std::string& kw) {
    if (!b.cards.empty()) m.end_time = fields_of(b.cards[0], kW10).real(0, "ENDTIM");
  }

  void read_control_timestep(const Block& b, [[maybe_unused]] const std::string& kw) {
    if (!b.cards.empty()) {
      Card c = fields_of(b.cards[0], kW10);
      double s = c.real_or(1, "TSSFAC", 0.9);
      if (s > 0.0) m.dt_scale = s;
      m.dt2ms = c.real_or(4, "DT2MS", 0.0);
    }
  }

  void read_control_hourglass(const Block& b, [[maybe_unused]] const std::string& kw) {
    if (!b.cards.empty()) {
      Card c = fields_of(b.cards[0], kW10);
      long ihq = c.integer_or(0, "IHQ", 1);
      if (ihq > 3)
        substitute(c.where, "*CONTROL_HOURGLASS IHQ " + std::to_string(ihq), "viscous hourglass control (IHQ 1-3)");
      m.hourglass_q = c.real_or(1, "QH", 0.1);
    }
  }

  void read_control_solid(const Block& b, const std::string& kw) {
    // ESORT FMATRIX NIPTETS SWLOCL PSFAIL T10JTOL ICOH TET13K; then PM1-10.
    // NIPTETS, T10JTOL and TET13K set elements this reader refuses (10-node
    // and nodal-pressure tetrahedra); SWLOCL the output's axes (ours are global).
    for (size_t card = 0; card < b.cards.size(); ++card) {
      const Card c = fields_of(b.cards[card], kW10);
      for (size_t k = 0; k < c.fields.size(); ++k) {
        if (c.fields[k].empty()) continue;
        if (card == 0 && k == 0) {
          const long esort = c.integer(0, "ESORT");
          if (esort != 0 && esort != 1) c.fail("ESORT " + std::to_string(esort) + ": 0 or 1 (tetrahedra sorted to ELFORM 10)");
          sort_tetrahedra = esort == 1;
        } else if (card == 0 && (k == 2 || k == 5 || k == 7)) {
        } else if (card == 0 && k == 3) {
          if (c.integer(3, "SWLOCL") == 2) warn(c.where, "SWLOCL 2: solid stresses are written in global axes all the same");
        } else if (c.real(k, "field") != 0.0) {
          c.fail(kw + " field " + std::to_string(k + 1) + " ('" + c.fields[k] + "') is not read by this fe_server version "
                 "and is not LS-DYNA's default: ignoring it would change the result");
        }
      }
    }
    warn(b.where, kw + ": ESORT is read (" + (sort_tetrahedra ? "1: tetrahedra of ELFORM 1 parts run as ELFORM 10" : "0") +
                      "); its other fields hold LS-DYNA's defaults or set elements this deck cannot have");
  }

  void read_control_bulk_viscosity(const Block& b, [[maybe_unused]] const std::string& kw) {
    if (!b.cards.empty()) {
      Card c = fields_of(b.cards[0], kW10);
      m.bulk_q1 = c.real_or(0, "Q1", 1.5);
      m.bulk_q2 = c.real_or(1, "Q2", 0.06);
    }
  }

  void read_database_binary_d3plot(const Block& b, [[maybe_unused]] const std::string& kw) {
    // Field snapshots every DT, written as HDF5 + XDMF (not d3plot).
    if (!b.cards.empty()) m.snapshot_interval = fields_of(b.cards[0], kW10).real(0, "DT");
  }

  void read_database_glstat(const Block& b, [[maybe_unused]] const std::string& kw) {
    // Card 1: DT, BINARY (LCUR, IOOPT: not used). The history file's rows
    // at DT (output/history.hpp); DT at or below the FE step: every step.
    // GLSTAT, MATSUM, RCFORC, NODOUT and ELOUT also write LS-DYNA's ASCII
    // file of that name (output/ascii_output.hpp) as BINARY asks: LS-DYNA's
    // 1 (or blank) is the ASCII file, 2 its binary database only (binout;
    // here the HDF5 history, which is always written), 3 both.
    if (b.cards.empty()) b.fail(kw + " needs its card with DT");
    Card c = fields_of(b.cards[0], kW10);
    const double dt = c.real(0, "DT");
    if (!(dt > 0.0)) c.fail("DT must be positive");
    const long binary = c.integer_or(1, "BINARY", 0);
    if (binary < 0 || binary > 3)
      c.fail("BINARY must be 1 (the ASCII file), 2 (the binary history only: fe_server's HDF5) or 3 (both), got " +
             std::to_string(binary));
    if (kw != "*DATABASE_SECFORC" && binary != 2) {
      double& ascii = m.ascii_dt[config::to_lower(kw.substr(10))];
      ascii = ascii > 0.0 ? std::min(ascii, dt) : dt;
    }
    if (kw == "*DATABASE_ELOUT") elout_where = b.where;
    if (kw != "*DATABASE_MATSUM") {  // the HDF5 has no per-part stream
      double& to = kw == "*DATABASE_NODOUT"                                   ? m.history_dt_nodes
                   : kw == "*DATABASE_ELOUT" || kw == "*DATABASE_SECFORC" ? m.history_dt_elements
                                                                          : m.history_dt_global;
      to = to > 0.0 ? std::min(to, dt) : dt;
    }
  }

  void read_database_history_node(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (int id : id_list(b, 0, "ID")) m.history_nodes.push_back(m.index_of(id, b.where));
  }

  void read_database_history_solid(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (int id : id_list(b, 0, "ID")) m.history_solids.push_back(id);  // resolved after the elements
  }

  void read_database_history_beam(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (int id : id_list(b, 0, "ID")) m.history_bars.push_back(id);  // resolved after the elements
  }

  void read_database_history_shell(const Block& b, [[maybe_unused]] const std::string& kw) {
    for (int id : id_list(b, 0, "ID")) m.history_axis.push_back(id);  // resolved after the elements
  }

  void read_contact_2d_automatic_surface_to_surface(const Block& b, [[maybe_unused]] const std::string& kw) {
    // Card 1: SIDS, SIDM (part sets whose outer boundaries meet), SFACT,
    // FREQ, FS, FD, DC, MEMBS; card 2 (TBIRTH, ...) is not used; an optional
    // card 3: VC, VDC (damping, % of critical; 20 when not given, as for
    // the 3D contact).
    if (b.cards.empty()) b.fail(kw + " needs card 1 (SIDS, SIDM, ...)");
    Card c1 = fields_of(b.cards[0], kW10);
    ContactDef d;
    d.where = c1.where;
    d.planar = true;
    d.slave_set = static_cast<int>(c1.integer(0, "SIDS"));
    d.master_set = static_cast<int>(c1.integer(1, "SIDM"));
    if (d.slave_set <= 0 || d.master_set <= 0)
      c1.fail("SIDS and SIDM must be part sets (> 0); node sets (< 0) are not supported");
    d.stiffness_factor = c1.real_or(2, "SFACT", 1.0);
    if (d.stiffness_factor <= 0.0) d.stiffness_factor = 1.0;
    warn_stiffness_cap(d, "SFACT");
    friction(c1, 4, d);
    if (b.cards.size() > 2) {
      const Card c3 = fields_of(b.cards[2], kW10);
      d.vc = c3.real_or(0, "VC", 0.0);
      d.damping = c3.real_or(1, "VDC", 20.0) / 100.0;
    }
    check_friction(c1, d);
    m.contacts.push_back(d);
  }

  // LS-DYNA's output requests (its manual, Vol. I, *DATABASE): those fe_server
  // reads (first group) and those it ignores with a warning (the rest).
  static const std::vector<std::string>& database_keywords() {
    static const std::vector<std::string> k = {
        "*DATABASE_BINARY_D3PLOT", "*DATABASE_CROSS_SECTION_SET", "*DATABASE_ELOUT", "*DATABASE_GLSTAT",
        "*DATABASE_HISTORY_BEAM", "*DATABASE_HISTORY_NODE", "*DATABASE_HISTORY_SHELL", "*DATABASE_HISTORY_SOLID",
        "*DATABASE_MATSUM", "*DATABASE_NODOUT", "*DATABASE_RCFORC", "*DATABASE_SECFORC",
        // output LS-DYNA writes and fe_server does not
        "*DATABASE_ABSTAT", "*DATABASE_ATDOUT", "*DATABASE_AVSFLT", "*DATABASE_BEARING", "*DATABASE_BINARY_BLSTFOR",
        "*DATABASE_BINARY_D3CRACK", "*DATABASE_BINARY_D3DUMP", "*DATABASE_BINARY_D3PART", "*DATABASE_BINARY_D3THDT",
        "*DATABASE_BINARY_FSIFOR", "*DATABASE_BINARY_INTFOR", "*DATABASE_BINARY_RUNRSF", "*DATABASE_BINARY_XTFILE",
        "*DATABASE_BNDOUT", "*DATABASE_CPM_SENSOR", "*DATABASE_CROSS_SECTION_PLANE", "*DATABASE_CURVOUT",
        "*DATABASE_DCFAIL", "*DATABASE_DEFGEO", "*DATABASE_DEFORC", "*DATABASE_DEMASSFLOW", "*DATABASE_DISBOUT",
        "*DATABASE_EXTENT_AVS", "*DATABASE_EXTENT_BINARY", "*DATABASE_EXTENT_BINARY_COMP", "*DATABASE_EXTENT_D3PART",
        "*DATABASE_EXTENT_INTFOR", "*DATABASE_EXTENT_MOVIE", "*DATABASE_EXTENT_MPGS", "*DATABASE_EXTENT_SSSTAT",
        "*DATABASE_FORMAT", "*DATABASE_FREQUENCY_ASCII", "*DATABASE_FREQUENCY_BINARY", "*DATABASE_FSI",
        "*DATABASE_FREQUENCY_BINARY_D3ACS", "*DATABASE_FREQUENCY_BINARY_D3ATV", "*DATABASE_FREQUENCY_BINARY_D3FTG",
        "*DATABASE_FREQUENCY_BINARY_D3PSD", "*DATABASE_FREQUENCY_BINARY_D3RMS", "*DATABASE_FREQUENCY_BINARY_D3SPCM",
        "*DATABASE_FREQUENCY_BINARY_D3SSD", "*DATABASE_FREQUENCY_BINARY_D3ZCF", "*DATABASE_FREQUENCY_ASCII_NODOUT_PSD",
        "*DATABASE_FREQUENCY_ASCII_ELOUT_PSD", "*DATABASE_FREQUENCY_ASCII_NODOUT_SSD", "*DATABASE_FREQUENCY_ASCII_ELOUT_SSD",
        "*DATABASE_GCEOUT", "*DATABASE_HISTORY_DISCRETE", "*DATABASE_HISTORY_NODE_SET", "*DATABASE_HISTORY_SOLID_SET",
        "*DATABASE_HISTORY_SHELL_SET", "*DATABASE_HISTORY_BEAM_SET", "*DATABASE_HISTORY_TSHELL", "*DATABASE_HISTORY_SPH",
        "*DATABASE_JNTFORC", "*DATABASE_MASSOUT", "*DATABASE_MOVIE", "*DATABASE_MPGS", "*DATABASE_NCFORC",
        "*DATABASE_NODAL_FORCE_GROUP", "*DATABASE_NODFOR", "*DATABASE_PBSTAT", "*DATABASE_PLLYOUT", "*DATABASE_PRTUBE",
        "*DATABASE_PROFILE", "*DATABASE_PWP_OUTPUT", "*DATABASE_RBDOUT", "*DATABASE_RWFORC", "*DATABASE_SBTOUT",
        "*DATABASE_SLEOUT", "*DATABASE_SPCFORC", "*DATABASE_SPHOUT", "*DATABASE_SPHMASSFLOW", "*DATABASE_SSSTAT",
        "*DATABASE_SSSTAT_MASS_RATIO", "*DATABASE_SUPERPLASTIC_FORMING", "*DATABASE_SWFORC", "*DATABASE_TPRINT",
        "*DATABASE_TRACER", "*DATABASE_TRHIST"};
    return k;
  }
  static bool known_database_keyword(const std::string& kw) {
    const auto& k = database_keywords();
    return std::find(k.begin(), k.end(), kw) != k.end();
  }
  // The known keyword fewest edits away, if it is within a third of the name.
  static std::string nearest_database_keyword(const std::string& kw) {
    return config::nearest(kw, database_keywords());
  }

  // Run controls that set how LS-DYNA runs, never what it computes: the CPU
  // count, its decomposition and its restart dumps. fe_server's results do
  // not depend on the thread or rank count (solver.hpp), so none of their
  // fields can change one.
  static const char* run_control_note(const std::string& kw) {
    if (kw == "*CONTROL_PARALLEL")
      return "sets LS-DYNA's CPU count and summation order (fe_server: --threads; its results are the same for any "
             "count)";
    if (kw.rfind("*CONTROL_MPP_IO_", 0) == 0) return "sets LS-DYNA's MPP dump files";
    if (kw.rfind("*CONTROL_MPP_DECOMPOSITION_", 0) == 0)
      return "sets LS-DYNA's MPP domain decomposition (fe_server partitions with METIS; results as on one rank)";
    return nullptr;
  }

  // LS-DYNA's default of a *CONTROL_ field (card and field from 0) where it
  // is not 0, as its keyword manual gives them: a deck that writes them out
  // (LS-PrePost does) asks for nothing else than a blank card or a 0.
  static double control_default(const std::string& kw, size_t card, size_t field) {
    for (const ControlDefault& d : control_defaults())
      if (kw == d.keyword && card == d.card && field == d.field) return d.value;
    return 0.0;
  }
  struct ControlDefault {
    const char* keyword;
    size_t card, field;
    double value;
    const char* name;
  };
  static const std::vector<ControlDefault>& control_defaults() {
    static const std::vector<ControlDefault> kDefaults = {
        {"*CONTROL_CONTACT", 0, 0, 0.1, "SLSFAC"},
        {"*CONTROL_CONTACT", 0, 2, 1.0, "ISLCHK"},
        {"*CONTROL_CONTACT", 0, 4, 1.0, "PENOPT"},
        {"*CONTROL_CONTACT", 0, 6, 1.0, "ORIEN"},
        {"*CONTROL_CONTACT", 1, 4, 4.0, "XPENE"},
        {"*CONTROL_CONTACT", 4, 2, 1.0, "RWGAPS"},
        {"*CONTROL_CONTACT", 4, 4, 1.0, "RWKSF"},
        {"*CONTROL_SHELL", 0, 0, 20.0, "WRPANG"},
        {"*CONTROL_SHELL", 0, 2, -1.0, "IRNXX"},
        {"*CONTROL_SHELL", 0, 4, 2.0, "THEORY"},
        {"*CONTROL_SHELL", 0, 5, 2.0, "BWC"},
        {"*CONTROL_SHELL", 0, 6, 1.0, "MITER"},
        {"*CONTROL_SHELL", 1, 0, 1.0, "ROTASCL"},
        {"*CONTROL_SHELL", 1, 3, 1.0, "CSTYP6"},
        {"*CONTROL_SHELL", 2, 4, 2.0, "IRQUAD"},
        {"*CONTROL_SOLID", 0, 2, 4.0, "NIPTETS"},
        {"*CONTROL_SOLID", 0, 3, 1.0, "SWLOCL"},
        {"*CONTROL_ACCURACY", 0, 1, 1.0, "INN"},
    };
    return kDefaults;
  }

  // Keywords users' decks carry that this reader refuses, with what the
  // refusal means for the model and what to do instead.
  static const std::vector<std::pair<const char*, const char*>>& refusals() {
    static const std::vector<std::pair<const char*, const char*>> kReasons = {
        {"*MAT_NULL", "fluids with an equation of state are not modelled (a percussion unit's oil is the host's: "
                      "give its cavities as *USER_LOADING_SET ports)"},
        {"*EOS_", "equations of state (for *MAT_NULL fluids) are not modelled (a percussion unit's oil is the "
                  "host's: give its cavities as *USER_LOADING_SET ports)"},
        {"*MAT_ADD_EROSION", "element erosion is not modelled: without it no element would fail, so the deck is refused"},
        {"*CONTACT_ERODING_", "eroding contact needs element erosion, which is not modelled"},
        {"*SECTION_SPH", "SPH particles are not modelled"},
        {"*ELEMENT_SPH", "SPH particles are not modelled"},
        {"*SECTION_TSHELL", "thick shells are not modelled: mesh the part with solids (*ELEMENT_SOLID)"},
        {"*ELEMENT_TSHELL", "thick shells are not modelled: mesh the part with solids (*ELEMENT_SOLID)"},
        {"*CONTROL_IMPLICIT_", "fe_server is explicit only (central differences): implicit statics, eigenvalues and "
                               "implicit dynamics are not available"},
        {"*FREQUENCY_DOMAIN_", "frequency-domain analyses are not available: fe_server integrates in time"},
        {"*CONSTRAINED_JOINT_", "joints are not modelled: tie the parts (*CONTACT_TIED_...) or merge them as rigid "
                                "bodies (*CONSTRAINED_RIGID_BODIES)"},
        {"*DAMPING_FREQUENCY_RANGE", "Arup's frequency-independent damping is LS-DYNA's own formulation and is not "
                                     "reproduced: give Rayleigh damping, *DAMPING_PART_STIFFNESS with COEF = -beta "
                                     "(and *DAMPING_PART_MASS), tuned to the band you mean"},
        {"*HOURGLASS", "per-part hourglass control is not read: *CONTROL_HOURGLASS sets it for the whole model"},
    };
    return kReasons;
  }
  static const char* refusal_reason(const std::string& kw) {
    for (const auto& [prefix, why] : refusals())
      if (kw.rfind(prefix, 0) == 0) return why;
    return nullptr;
  }

  // A keyword this reader does not read is ignored only where that provably
  // changes no result: output requests (fe_server writes its own HDF5), and
  // *CONTROL_ cards that hold nothing but blanks and zeros (LS-DYNA's
  // defaults). Anything else is an error with its line.
  void unsupported(const Block& b) {
    // A _TITLE or _ID the grammar did not take off (deck_grammar.cpp): of a
    // keyword read here, the option is what is missing; else the refusal
    // is the keyword's own.
    std::string kw = b.keyword;
    for (const std::string suffix : {"_ID", "_TITLE"})
      if (kw != "*TITLE" && kw.size() > suffix.size() && kw.compare(kw.size() - suffix.size(), suffix.size(), suffix) == 0) {
        const std::string base = kw.substr(0, kw.size() - suffix.size());
        if (keyword_index().count(base))
          b.fail(base + " is read by this fe_server version, but not its " + suffix + " form: give it without the " +
                 (suffix == "_ID" ? "ID card" : "title card"));
        kw = base;
        break;
      }
    if (kw.rfind("*DATABASE_", 0) == 0 && !known_database_keyword(kw)) {
      // A misspelt output request would silently write nothing.
      const std::string near = nearest_database_keyword(kw);
      b.fail(kw + " is not one of LS-DYNA's *DATABASE_ keywords" +
             (near.empty() ? std::string() : " (did you mean " + near + "?)"));
    }
    if (kw.rfind("*DATABASE_", 0) == 0 || kw == "*CONTROL_OUTPUT" || kw == "*CONTROL_ENERGY" || kw == "*CONTROL_CPU") {
      warn(b.where, kw + " asks for LS-DYNA's output files or limits: fe_server writes its own results (HDF5), ignored");
      return;
    }
    if (kw.rfind("*CASE", 0) == 0)
      b.fail(kw + ": load cases (*CASE) are not supported; their contents would apply to every case: run each case as "
                  "its own deck");
    if (const char* note = run_control_note(kw)) {
      warn(b.where, kw + " " + note + ": it changes no result here, ignored");
      return;
    }
    const char* why = refusal_reason(kw);
    if (why && kw.rfind("*CONTROL_", 0) != 0) b.fail(kw + " is not supported by this fe_server version: " + why);
    if (kw.rfind("*CONTROL_", 0) == 0) {
      for (size_t card = 0; card < b.cards.size(); ++card) {
        const Card c = fields_of(b.cards[card], kW10);
        for (size_t k = 0; k < c.fields.size(); ++k) {
          if (c.fields[k].empty()) continue;
          double v = 1.0;
          try {
            v = config::parse_real(c.fields[k], c.where, "");
          } catch (const InputError&) {
          }
          if (v != 0.0 && v != control_default(kw, card, k))  // 0 is LS-DYNA's "the default" too
            c.fail(kw + " is not supported by this fe_server version and field " + std::to_string(k + 1) + " ('" +
                   c.fields[k] + "') is not LS-DYNA's default: ignoring it would change the result" +
                   (why ? std::string(" (") + why + ")" : std::string()));
        }
      }
      warn(b.where, kw + " is not supported; its cards hold only LS-DYNA's defaults, ignored");
      return;
    }
    b.fail("keyword " + kw + " is not supported by this fe_server version; ignoring it could change the result");
  }

  void mass_damping(const DampingCards& d) {
    const Card& c = d.c1;
    MassDamping md;
    md.where = c.where;
    // The translational scale factors; all of them blank or 0 means 1 (LS-DYNA).
    auto scales = [&](const Card& card, size_t first) {
      Vec3 st(card.real_or(first, "STX", 0.0), card.real_or(first + 1, "STY", 0.0), card.real_or(first + 2, "STZ", 0.0));
      return st.isZero() ? Vec3(Vec3::Ones()) : st;
    };
    if (d.part) {
      const long pid = c.integer(0, "PID");
      auto part = m.parts.find(static_cast<int>(pid));
      if (part == m.parts.end()) c.fail("PID " + std::to_string(pid) + " is not a *PART");
      if (!m.materials.count(part->second.material))
        c.fail("part " + std::to_string(pid) + " is a spring or damper part: mass damping acts on the nodes of "
               "solid, axisymmetric or bar parts");
      if (m.materials.at(part->second.material).rigid)
        c.fail("part " + std::to_string(pid) + " is rigid: mass damping of rigid bodies is not supported");
      md.all_nodes = false;
      md.nodes = nodes_of_parts({static_cast<int>(pid)});
      md.curve_id = static_cast<int>(c.integer(1, "LCID"));
      md.sf = c.real_or(2, "SF", 1.0);
      if (!d.c2.fields.empty()) md.scale = scales(d.c2, 0);
    } else {
      md.curve_id = static_cast<int>(c.integer_or(0, "LCID", 0));
      md.value = c.real_or(1, "VALDMP", 0.0);
      md.scale = scales(c, 2);
      if (md.curve_id == 0 && md.value == 0.0) return;  // no damping
      if (!m.rigid_bodies.empty() || std::any_of(m.materials.begin(), m.materials.end(), [](const auto& kv) { return kv.second.rigid; }))
        substitute(c.where, "*DAMPING_GLOBAL on a model with rigid bodies", "damping of the deformable nodes only (rigid bodies undamped)");
    }
    if (md.curve_id != 0 && !m.curves.count(md.curve_id))
      c.fail("LCID " + std::to_string(md.curve_id) + " is not defined by a *DEFINE_CURVE");
    m.mass_damping.push_back(md);
  }

  // *LOAD_SEGMENT: LCID SF AT N1 N2 N3 N4; *LOAD_SEGMENT_SET: SSID LCID SF AT.
  void segment_pressure(const Card& c, bool is_set) {
    SegmentPressure p;
    p.where = c.where;
    const size_t f = is_set ? 1 : 0;  // LCID's field
    p.curve_id = static_cast<int>(c.integer(f, "LCID"));
    if (!m.curves.count(p.curve_id)) c.fail("LCID " + std::to_string(p.curve_id) + " is not defined by a *DEFINE_CURVE");
    p.sf = c.real_or(f + 1, "SF", 1.0);
    p.at = c.real_or(f + 2, "AT", 0.0);
    if (is_set) {
      const long sid = c.integer(0, "SSID");
      auto it = m.segment_sets.find(static_cast<int>(sid));
      if (it == m.segment_sets.end()) c.fail("segment set " + std::to_string(sid) + " is not defined in *SET_SEGMENT");
      p.segments = it->second;
    } else {
      Segment s;
      const long n3 = c.integer_or(5, "N3", 0), n4 = c.integer_or(6, "N4", 0);
      s.n[0] = m.index_of(static_cast<int>(c.integer(3, "N1")), c.where);
      s.n[1] = m.index_of(static_cast<int>(c.integer(4, "N2")), c.where);
      if (n3 == 0) {
        if (n4 != 0) c.fail("N3 is blank but N4 is not");
        s.n[2] = s.n[3] = -1;  // a 2D line
      } else {
        s.n[2] = m.index_of(static_cast<int>(n3), c.where);
        s.n[3] = n4 == 0 ? s.n[2] : m.index_of(static_cast<int>(n4), c.where);
      }
      p.segments.push_back(s);
    }
    for (const Segment& s : p.segments)
      if (s.line() && m.axis.empty()) c.fail("a 2-node segment is a 2D line: only an axisymmetric deck has those");
    m.segment_pressures.push_back(p);
  }

  std::vector<int> nodes_of_set(int sid, const Card& c) {
    auto it = m.node_sets.find(sid);
    if (it == m.node_sets.end()) c.fail("node set " + std::to_string(sid) + " is not defined in *SET_NODE_LIST");
    std::vector<int> idx;
    for (int id : it->second) idx.push_back(m.index_of(id, c.where));
    return idx;
  }
  std::vector<int> nodes_of_parts(const std::set<int>& pids) {
    std::set<int> nodes;
    for (const auto& e : m.solids)
      if (pids.count(e.part)) nodes.insert(e.n, e.n + 8);
    for (const auto& e : m.bars)
      if (pids.count(e.part)) {
        nodes.insert(e.n1);
        nodes.insert(e.n2);
      }
    for (const auto& e : m.axis)
      if (pids.count(e.part)) nodes.insert(e.n, e.n + 4);
    return {nodes.begin(), nodes.end()};
  }

  // The outer boundary of the axisymmetric elements of a part set, as line
  // segments with the body on their left: the edges that belong to one
  // element only, in that element's counter-clockwise direction. Edges on
  // the axis (r = 0 at both ends) bound the mesh but no surface: the solid
  // continues through the axis, so nothing can touch them (taken as
  // contact lines, a node resting on the part's face would be "behind" them).
  std::vector<Segment> boundary_of_part_set(int sid, const config::SourceLocation& where) {
    auto it = m.part_sets.find(sid);
    if (it == m.part_sets.end()) throw InputError(where, "part set " + std::to_string(sid) + " is not defined");
    const std::set<int> pids(it->second.begin(), it->second.end());
    std::map<std::pair<int, int>, int> edges;  // undirected edge → elements that have it
    std::vector<std::pair<int, int>> order;    // each edge once, directed as its first element has it
    for (const auto& e : m.axis) {
      if (!pids.count(e.part)) continue;
      for (int k = 0; k < 4; ++k) {
        const int a = e.n[k], b = e.n[(k + 1) % 4];
        if (a == b) continue;  // the collapsed edge of a triangle
        if (edges[std::minmax(a, b)]++ == 0) order.push_back({a, b});
      }
    }
    std::vector<Segment> out;
    for (const auto& [a, b] : order) {
      if (edges[std::minmax(a, b)] != 1) continue;
      if (on_axis(m.x0[static_cast<size_t>(a)]) && on_axis(m.x0[static_cast<size_t>(b)])) continue;
      Segment s;
      s.n[0] = a, s.n[1] = b, s.n[2] = s.n[3] = -1;
      out.push_back(s);
    }
    if (out.empty())
      throw InputError(where, "part set " + std::to_string(sid) + " has no axisymmetric elements to contact");
    return out;
  }

  // A two-sided contact's card 1: SSID MSID SSTYP MSTYP, segment sets or a
  // slave node set (SSTYP 4, the default of the _NODES_TO_SURFACE forms).
  void contact_card_1(const Block& b, bool nodes_to_surface, int& slave, int& master, bool& slave_nodes,
                      config::SourceLocation& where) {
    if (b.cards.empty()) b.fail(b.keyword + " needs card 1 (SSID, MSID, SSTYP, MSTYP)");
    Card c1 = fields_of(b.cards[0], kW10);
    where = c1.where;
    slave = static_cast<int>(c1.integer(0, "SSID"));
    master = static_cast<int>(c1.integer(1, "MSID"));
    const long sstyp = c1.integer_or(2, "SSTYP", nodes_to_surface ? 4 : 0);
    if ((sstyp != 0 && sstyp != 4) || c1.integer_or(3, "MSTYP", 0) != 0)
      c1.fail("SSTYP must be 0 (segment set) or 4 (node set) and MSTYP 0 (segment set) in this version");
    slave_nodes = sstyp == 4;
  }

  // FS, FD and DC from fields k, k+1, k+2 of card c.
  static void friction(const Card& c, size_t k, ContactDef& d) {
    d.fs = c.real_or(k, "FS", 0.0);
    d.fd = c.real_or(k + 1, "FD", 0.0);
    d.dc = c.real_or(k + 2, "DC", 0.0);
  }
  static void check_friction(const Card& c, const ContactDef& d) {
    if (d.fs < 0.0 || d.fd < 0.0 || d.dc < 0.0 || d.vc < 0.0)
      c.fail("FS, FD, DC and VC must not be negative (LS-DYNA's FS < 0 friction tables are not supported)");
  }

  // A contact's card 2 (FS FD DC VC VDC: Coulomb friction, and the damping
  // in % of critical, 20 when not given) and card 3 (SFS), shared by the 3D
  // contacts.
  void contact_cards_2_and_3(const Block& b, ContactDef& d) {
    if (b.cards.size() > 1) {
      Card c2 = fields_of(b.cards[1], kW10);
      friction(c2, 0, d);
      d.vc = c2.real_or(3, "VC", 0.0);
      d.damping = c2.real_or(4, "VDC", 20.0) / 100.0;
      check_friction(c2, d);
    }
    if (b.cards.size() > 2) d.stiffness_factor = fields_of(b.cards[2], kW10).real_or(0, "SFS", 1.0);
    if (d.stiffness_factor <= 0.0) d.stiffness_factor = 1.0;
    warn_stiffness_cap(d, "SFS");
  }

  // A face's distinct nodes, sorted, padded with −1: the same key for a
  // triangle whichever corner its element repeats (n1 n2 n3 n3 of one
  // tetrahedron is n3 n1 n2 n2 of its neighbour).
  static std::array<int, 4> face_key(const Segment& s) {
    std::array<int, 4> key{s.n[0], s.n[1], s.n[2], s.n[3]};
    std::sort(key.begin(), key.end());
    const auto end = std::unique(key.begin(), key.end());
    std::fill(end, key.end(), -1);
    return key;
  }

  // The outer faces of the solids of parts `pids`: the faces only one
  // element has, their nodes ordered so the normal points out of it.
  std::vector<Segment> outer_faces_of(const std::set<int>& pids, const config::SourceLocation& where) {
    // Each face of a hex (nodes 0–3 one end, 4–7 the other), counter-clockwise seen from outside.
    static constexpr int kFace[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    std::map<std::array<int, 4>, int> count;
    std::vector<Segment> faces;
    for (const auto& e : m.solids) {
      if (!pids.count(e.part)) continue;
      for (const auto& f : kFace) {
        Segment s;
        for (int k = 0; k < 4; ++k) s.n[k] = e.n[f[k]];
        const std::array<int, 4> key = face_key(s);
        if (key[2] < 0) continue;  // a collapsed face of a wedge or tet
        if (count[key]++ == 0) faces.push_back(s);
      }
    }
    std::vector<Segment> out;
    for (const Segment& s : faces) {
      if (count[face_key(s)] != 1) continue;
      Segment t = s;
      // A triangle keeps its three corners with n[3] == n[2].
      if (t.n[0] == t.n[1]) t = Segment{{t.n[1], t.n[2], t.n[3], t.n[3]}};
      else if (t.n[1] == t.n[2]) t = Segment{{t.n[0], t.n[1], t.n[3], t.n[3]}};
      else if (t.n[3] == t.n[0]) t = Segment{{t.n[0], t.n[1], t.n[2], t.n[2]}};
      out.push_back(t);
    }
    if (out.empty()) throw InputError(where, "the single-surface contact's parts have no solid elements");
    return out;
  }

  void finish(const std::string& name) {
    if (m.node_ids.empty()) throw InputError({name, 1}, "the deck defines no nodes (*NODE)");
    const size_t n = m.node_ids.size();
    m.v0.assign(n, Vec3::Zero());
    resolve_set_unions();
    for (const auto& [mid, c] : hardening_curves) {
      const long lcss = c.integer(2, "LCSS");
      auto curve = m.curves.find(static_cast<int>(lcss));
      if (curve == m.curves.end()) c.fail("LCSS " + std::to_string(lcss) + " is not defined by a *DEFINE_CURVE");
      Material& mat = m.materials.at(mid);
      mat.hardening_strain.clear();
      mat.hardening_stress.clear();
      for (size_t k = 0; k < curve->second.a.size(); ++k) {
        mat.hardening_strain.push_back(curve->second.sfa * curve->second.a[k] + curve->second.offa);
        mat.hardening_stress.push_back(curve->second.sfo * curve->second.o[k] + curve->second.offo);
      }
      if (mat.hardening_strain.size() < 2) c.fail("LCSS " + std::to_string(lcss) + " needs at least two points");
    }
    elements();
    constrain_axisymmetric_nodes();
    if (!m.axis.empty()) {
      m.symmetry_axis = 1;  // LS-DYNA's 2D convention: y is the axis
      if (!m.solids.empty())
        throw InputError(solid_cards.front().where,
                         "a deck is either 3D (solids, axis z) or 2D axisymmetric (shells, axis y): this one has both");
    } else if (!line_set_cards.empty()) {
      line_set_cards.front().fail("a *SET_SEGMENT of two nodes is a 2D line: only an axisymmetric deck has those");
    }
    for (const Card& c : mass_cards) {
      double mass = c.real(2, "MASS");
      if (!(mass > 0.0)) c.fail("MASS must be positive");
      m.mass[static_cast<size_t>(m.index_of(static_cast<int>(c.integer(1, "NID")), c.where))] += mass;
    }
    for (const Card& c : discrete_cards) discrete(c);
    for (const Card& c : spc_cards) spc(c, {m.index_of(static_cast<int>(c.integer(0, "NID")), c.where)});
    for (const Card& c : spc_set_cards) spc(c, nodes_of_set(static_cast<int>(c.integer(0, "NSID")), c));
    for (const auto& [c, is_set] : motion_cards) prescribed_motion(c, is_set);
    for (const Card& c : rigid_motion_cards) prescribed_motion(c, false, true);
    for (const auto& [c, is_set] : pressure_cards) segment_pressure(c, is_set);
    for (const auto& [c, is_set] : nodal_load_cards) {
      NodalLoad l;
      l.where = c.where;
      l.nodes = is_set ? nodes_of_set(static_cast<int>(c.integer(0, "NSID")), c)
                       : std::vector<int>{m.index_of(static_cast<int>(c.integer(0, "NID")), c.where)};
      const long dof = c.integer(1, "DOF");
      if (dof < 1 || dof > 3)
        c.fail("DOF " + std::to_string(dof) + ": only 1, 2, 3 (a force along x, y, z) are supported, not moments or follower forces");
      l.dof = static_cast<int>(dof - 1);
      l.curve_id = static_cast<int>(c.integer(2, "LCID"));
      if (!m.curves.count(l.curve_id)) c.fail("LCID " + std::to_string(l.curve_id) + " is not defined by a *DEFINE_CURVE");
      l.sf = c.real_or(3, "SF", 1.0);
      if (c.integer_or(4, "CID", 0) != 0) c.fail("CID (a local coordinate system) is not supported");
      m.nodal_loads.push_back(l);
    }
    for (const DampingCards& d : damping_cards) mass_damping(d);
    for (const auto& [c, is_set] : stiffness_damping_cards) stiffness_damping(c, is_set);
    for (const auto& [c1, c2] : fatigue_cards) fatigue_part(c1, c2);
    if (has_body_parts) {
      // LS-DYNA: the body loads act on the parts of this set only.
      const long psid = body_parts_card.integer(0, "PSID");
      auto it = m.part_sets.find(static_cast<int>(psid));
      if (it == m.part_sets.end()) body_parts_card.fail("part set " + std::to_string(psid) + " is not defined");
      const std::vector<int> nodes = nodes_of_parts({it->second.begin(), it->second.end()});
      for (BodyLoad& l : m.body_loads) l.all_nodes = false, l.nodes = nodes;
    }
    for (const BodyLoad& l : m.body_loads)
      for (int id : {l.curve_id, l.curve_dr_id})
        if (id != 0 && !m.curves.count(id))
          throw InputError(l.where, "load curve " + std::to_string(id) + " is not defined by a *DEFINE_CURVE");
    for (const Card& c : vel_cards)
      m.v0[static_cast<size_t>(m.index_of(static_cast<int>(c.integer(0, "NID")), c.where))] =
          Vec3(c.real_or(1, "VX", 0), c.real_or(2, "VY", 0), c.real_or(3, "VZ", 0));
    for (const auto& [c1, c2] : vel_set_cards) {
      Vec3 v(c2.real_or(0, "VX", 0), c2.real_or(1, "VY", 0), c2.real_or(2, "VZ", 0));
      long nsid = c1.integer_or(0, "NSID", 0);
      if (nsid == 0)
        for (auto& vi : m.v0) vi = v;  // NSID 0: all nodes
      else
        for (int i : nodes_of_set(static_cast<int>(nsid), c1)) m.v0[static_cast<size_t>(i)] = v;
    }
    for (const auto& [c1, c2] : vel_gen_cards) {
      // ID, STYP (1 part set, 2 part, 3 node set), OMEGA, VX, VY, VZ.
      if (c1.real_or(2, "OMEGA", 0.0) != 0.0) c1.fail("OMEGA (initial rotation) is not supported yet");
      Vec3 v(c1.real_or(3, "VX", 0), c1.real_or(4, "VY", 0), c1.real_or(5, "VZ", 0));
      int id = static_cast<int>(c1.integer(0, "ID"));
      long styp = c1.integer(1, "STYP");
      std::vector<int> nodes;
      if (styp == 1) {
        auto it = m.part_sets.find(id);
        if (it == m.part_sets.end()) c1.fail("part set " + std::to_string(id) + " is not defined");
        nodes = nodes_of_parts({it->second.begin(), it->second.end()});
      } else if (styp == 2) {
        nodes = nodes_of_parts({id});
      } else if (styp == 3) {
        nodes = nodes_of_set(id, c1);
      } else {
        c1.fail("STYP must be 1 (part set), 2 (part) or 3 (node set)");
      }
      for (int i : nodes) m.v0[static_cast<size_t>(i)] = v;
    }
    if (m.relaxes())
      for (size_t i = 0; i < n; ++i)
        if (m.v0[i].squaredNorm() > 0.0)
          throw InputError(m.relaxation.where.file.empty() ? config::SourceLocation{name, 1} : m.relaxation.where,
                           "dynamic relaxation ends with every node at rest, so initial velocities (node " +
                               std::to_string(m.node_ids[i]) + ") cannot be combined with it");
    rigid_bodies();
    std::set<int> in_body;
    for (const auto& rb : m.rigid_bodies) in_body.insert(rb.nodes.begin(), rb.nodes.end());
    std::vector<Eigen::Matrix<bool, 3, 1>> held = m.fixed;  // fixed or prescribed
    for (const auto& p : m.prescribed)
      for (int i : p.nodes) held[static_cast<size_t>(i)][p.dof] = true;
    for (size_t i = 0; i < n; ++i)
      if (!in_body.count(static_cast<int>(i)) && !held[i].all() && !(m.mass[i] > 0.0))
        throw InputError({name, 1}, "node " + std::to_string(m.node_ids[i]) +
                                        " has no mass and is neither fixed nor part of a rigid body");
    for (auto& ls : m.loading_sets) {
      if (ls.body) {
        auto it = m.part_sets.find(ls.segment_set);
        if (it == m.part_sets.end())
          throw InputError(ls.where, "part set " + std::to_string(ls.segment_set) + " is not defined in *SET_PART_LIST");
        ls.body_nodes = nodes_of_parts({it->second.begin(), it->second.end()});
        if (ls.body_nodes.empty())
          throw InputError(ls.where, "part set " + std::to_string(ls.segment_set) + " has no elements to load");
        continue;
      }
      if (ls.force && !m.node_sets.count(ls.segment_set))
        throw InputError(ls.where, "node set " + std::to_string(ls.segment_set) + " is not defined in *SET_NODE_LIST");
      if (!ls.force && !m.segment_sets.count(ls.segment_set))
        throw InputError(ls.where, "segment set " + std::to_string(ls.segment_set) + " is not defined in *SET_SEGMENT");
    }
    int planar_sets = 0;
    for (auto& c : m.contacts) {
      if (c.single_surface) {
        // The parts: a part set, one part, or every part; their solids'
        // outer faces become one built segment set (a negative id).
        std::set<int> pids;
        if (c.slave_set == 0) {
          for (const auto& [pid, part] : m.parts) pids.insert(pid);
        } else if (c.slave_nodes) {
          if (!m.parts.count(c.slave_set)) throw InputError(c.where, "part " + std::to_string(c.slave_set) + " is not defined");
          pids.insert(c.slave_set);
        } else {
          auto it = m.part_sets.find(c.slave_set);
          if (it == m.part_sets.end()) throw InputError(c.where, "part set " + std::to_string(c.slave_set) + " is not defined");
          pids.insert(it->second.begin(), it->second.end());
        }
        const int id = -(++planar_sets);
        m.segment_sets[id] = outer_faces_of(pids, c.where);
        c.part_ids.assign(pids.begin(), pids.end());
        c.slave_set = c.master_set = id;
        c.slave_nodes = false;
        continue;
      }
      if (!c.planar) continue;
      // Built segment sets get negative ids, which no deck can use.
      const int s_id = -(++planar_sets), m_id = -(++planar_sets);
      m.segment_sets[s_id] = boundary_of_part_set(c.slave_set, c.where);
      m.segment_sets[m_id] = boundary_of_part_set(c.master_set, c.where);
      c.slave_set = s_id, c.master_set = m_id;
    }
    for (const auto& c : m.contacts) {
      if (c.slave_nodes && !m.node_sets.count(c.slave_set))
        throw InputError(c.where, "contact node set " + std::to_string(c.slave_set) + " is not defined in *SET_NODE_LIST");
      for (int sid : {c.slave_set, c.master_set})
        if (!(c.slave_nodes && sid == c.slave_set) && !m.segment_sets.count(sid))
          throw InputError(c.where, "contact segment set " + std::to_string(sid) + " is not defined in *SET_SEGMENT");
    }
    for (const auto& t : m.ties) {
      if (t.slave_nodes && !m.node_sets.count(t.slave_set))
        throw InputError(t.where, "tied contact node set " + std::to_string(t.slave_set) + " is not defined in *SET_NODE_LIST");
      for (int sid : {t.slave_set, t.master_set})
        if (!(t.slave_nodes && sid == t.slave_set) && !m.segment_sets.count(sid))
          throw InputError(t.where, "tied contact segment set " + std::to_string(sid) + " is not defined in *SET_SEGMENT");
    }
    warn_point_loads_on_the_axis();
    // Element ids → indices, and the history lists (read as ids) resolved.
    auto index_of_ids = [](const auto& elements) {
      std::map<int, int> index;
      for (size_t i = 0; i < elements.size(); ++i) index[elements[i].id] = static_cast<int>(i);
      return index;
    };
    const std::map<int, int> solid_index = index_of_ids(m.solids), axi_index = index_of_ids(m.axis),
                             bar_index = index_of_ids(m.bars);
    auto resolve = [&](std::vector<int>& ids, const std::map<int, int>& index, const char* keyword, const char* kind) {
      for (int& id : ids) {
        auto it = index.find(id);
        if (it == index.end())
          throw InputError({name, 1}, std::string(keyword) + " names element " + std::to_string(id) + ", which is not " + kind);
        id = it->second;
      }
    };
    resolve(m.history_solids, solid_index, "*DATABASE_HISTORY_SOLID", "a solid element");
    resolve(m.history_axis, axi_index, "*DATABASE_HISTORY_SHELL", "an axisymmetric element");
    resolve(m.history_bars, bar_index, "*DATABASE_HISTORY_BEAM", "a 1D bar element");
    // LS-DYNA's elout lists the history solids; with none it would be a
    // header per DT and nothing else (the bars' and axisymmetric elements'
    // histories are in the HDF5 at ELOUT's DT all the same).
    if (m.ascii_dt.count("elout") && m.history_solids.empty()) {
      m.ascii_dt.erase("elout");
      warn(elout_where, "*DATABASE_ELOUT: the ASCII elout lists *DATABASE_HISTORY_SOLID elements and the deck has none: "
                        "not written (its DT still sets the HDF5 element history's rate)");
    }
    for (size_t k = 0; k < section_cards.size(); ++k) cross_section(section_cards[k], k, solid_index, axi_index, bar_index);
  }

  // One *DATABASE_CROSS_SECTION_SET card, resolved once the elements are known.
  void cross_section(const Card& c, size_t k, const std::map<int, int>& solid_index, const std::map<int, int>& axi_index,
                     const std::map<int, int>& bar_index) {
    CrossSection x;
    x.where = c.where;
    x.id = static_cast<int>(c.integer_or(6, "ID", static_cast<long>(k + 1)));
    for (int id : m.node_sets[static_cast<int>(c.integer(0, "NSID"))]) x.nodes.push_back(m.index_of(id, c.where));
    if (x.nodes.empty()) c.fail("NSID: the cut needs a node set of *SET_NODE_LIST");
    std::sort(x.nodes.begin(), x.nodes.end());
    auto resolve = [&](size_t field, const char* what, const std::map<int, std::vector<int>>& sets,
                       const std::map<int, int>& index, auto part_of, std::vector<int>& out) {
      const long sid = c.integer_or(field, what, 0);
      if (sid == 0) return;
      auto set = sets.find(static_cast<int>(sid));
      if (set == sets.end()) c.fail(std::string(what) + " " + std::to_string(sid) + " is not a defined element set");
      for (int id : set->second) {
        auto it = index.find(id);
        if (it == index.end()) c.fail(std::string(what) + ": element " + std::to_string(id) + " is not of that kind");
        if (m.materials.at(m.parts.at(part_of(it->second)).material).rigid)
          c.fail(std::string(what) + ": element " + std::to_string(id) + " is rigid: a section cuts deformable elements");
        out.push_back(it->second);
      }
    };
    resolve(1, "HSID", solid_sets, solid_index, [&](int e) { return m.solids[static_cast<size_t>(e)].part; }, x.solids);
    resolve(2, "BSID", beam_sets, bar_index, [&](int e) { return m.bars[static_cast<size_t>(e)].part; }, x.bars);
    resolve(3, "SSID", shell_sets, axi_index, [&](int e) { return m.axis[static_cast<size_t>(e)].part; }, x.axis);
    if (c.integer_or(4, "TSID", 0) != 0 || c.integer_or(5, "DSID", 0) != 0)
      c.fail("TSID and DSID (thick shells, discrete elements) are not supported in a cross section");
    if (x.solids.empty() && x.axis.empty() && x.bars.empty()) c.fail("the cross section names no element set");
    m.cross_sections.push_back(std::move(x));
  }

  // The ELFORM of a solid part's section (1 when the part has none).
  int solid_elform(int pid) const {
    const auto p = m.parts.find(pid);
    if (p == m.parts.end()) return 1;
    const auto sec = sections.find(p->second.section);
    return sec == sections.end() || (sec->second.first != 1 && sec->second.first != 10) ? 1 : sec->second.first;
  }

  const Material& material_of(int pid, const Card& c) {
    auto p = m.parts.find(pid);
    if (p == m.parts.end()) c.fail("part " + std::to_string(pid) + " is not defined in *PART");
    auto mat = m.materials.find(p->second.material);
    if (mat == m.materials.end())
      c.fail("part " + std::to_string(pid) + " has material " + std::to_string(p->second.material) +
             ", which is not defined by a *MAT_ keyword");
    return mat->second;
  }

  void elements() {
    m.mass.assign(m.node_ids.size(), 0.0);
    for (const Card& c : solid_cards) {
      SolidElement e;
      e.id = static_cast<int>(c.integer(0, "EID"));
      e.part = static_cast<int>(c.integer(1, "PID"));
      material_of(e.part, c);
      std::vector<int> ids;
      for (size_t k = 2; k < c.fields.size(); ++k)
        if (!c.fields[k].empty() && c.integer(k, "N") != 0) ids.push_back(static_cast<int>(c.integer(k, "N")));
      if (ids.size() > 8)
        c.fail("solid element " + std::to_string(e.id) + " has " + std::to_string(ids.size()) +
               " nodes: higher-order solids (10-node tetrahedra, 20-node hexahedra) are not supported");
      // A tetrahedron: four nodes, or LS-DYNA's eight with N4 repeated
      // (N4 = N5 = ... = N8), or N3 = N4 and N5 = ... = N8 (as the slots
      // hold it); its corners in the order they first appear. Other
      // repetitions are degenerate hexahedra (checked for volume below).
      std::vector<int> distinct;
      for (int id : ids)
        if (std::find(distinct.begin(), distinct.end(), id) == distinct.end()) distinct.push_back(id);
      const bool top_collapsed =
          ids.size() == 8 && ids[4] == ids[5] && ids[5] == ids[6] && ids[6] == ids[7];
      e.tet4 = distinct.size() == 4 &&
               (ids.size() == 4 || (top_collapsed && (ids[3] == ids[4] || ids[2] == ids[3])));
      const int elform = solid_elform(e.part);
      if (e.tet4) {
        ids = {distinct[0], distinct[1], distinct[2], distinct[2], distinct[3], distinct[3], distinct[3], distinct[3]};
        if (elform == 1 && !sort_tetrahedra && tet_in_hex_part.insert(e.part).second)
          substitute(c.where, "the tetrahedra of part " + std::to_string(e.part) +
                                  " (ELFORM 1: degenerate one-point hexahedra, whose centre point misplaces their "
                                  "mass by a quarter; *CONTROL_SOLID ESORT 1 sorts them to ELFORM 10, as LS-DYNA does)",
                      "ELFORM 10 (constant-strain tetrahedra)");
      } else if (elform == 10) {
        c.fail("solid element " + std::to_string(e.id) + " has " + std::to_string(distinct.size()) +
               " distinct nodes, but part " + std::to_string(e.part) + " is ELFORM 10: a tetrahedron has 4");
      }
      // A pyramid (its top face a point over four corners) as a one-point
      // hexahedron would lose a quarter of its mass (8·det J at the centre:
      // 1/4 where the unit pyramid has 1/3), as tetrahedra did.
      if (distinct.size() == 5 && top_collapsed)
        c.fail("solid element " + std::to_string(e.id) + " is a pyramid (5 nodes, N5 = ... = N8): as a degenerate "
               "one-point hexahedron it would lose a quarter of its mass; split it into two tetrahedra (ELFORM 10) "
               "or mesh without pyramids");
      if (ids.size() == 6) ids = {ids[0], ids[1], ids[2], ids[2], ids[3], ids[4], ids[5], ids[5]};  // wedge
      if (ids.size() != 8) c.fail("a solid element needs 4, 6 or 8 nodes, got " + std::to_string(ids.size()));
      for (int k = 0; k < 8; ++k) e.n[k] = m.index_of(ids[static_cast<size_t>(k)], c.where);
      // Lumped mass: ρ·V in the element's shares (an eighth to each slot of
      // a hexahedron, repeated corners of a wedge too; a quarter to each
      // corner of a tetrahedron).
      const double volume = solid_volume(hex8_gather(m.x0, e), e);
      if (!(volume > 0.0))
        c.fail("solid element " + std::to_string(e.id) + " is inverted or degenerate (volume " + std::to_string(volume) +
               "): check its node order (" +
               (e.tet4 ? "N1-N2-N3 counter-clockwise seen from N4" : "1-2-3-4 counter-clockwise seen from 5-6-7-8") + ")");
      const double rho = material_of(e.part, c).rho;
      for (int k = 0; k < 8; ++k) m.mass[static_cast<size_t>(e.n[k])] += rho * volume * solid_mass_share(e, k);
      m.solids.push_back(e);
    }
    for (const Card& c : beam_cards) {
      BarElement e;
      e.id = static_cast<int>(c.integer(0, "EID"));
      e.part = static_cast<int>(c.integer(1, "PID"));
      material_of(e.part, c);
      auto sec = sections.find(m.parts[e.part].section);
      if (sec == sections.end() || sec->second.first != 3)
        c.fail("part " + std::to_string(e.part) + " needs a *SECTION_BEAM with ELFORM 3 (truss)");
      m.parts[e.part].bar_area = sec->second.second;
      e.n1 = m.index_of(static_cast<int>(c.integer(2, "N1")), c.where);
      e.n2 = m.index_of(static_cast<int>(c.integer(3, "N2")), c.where);
      const double L = (m.x0[static_cast<size_t>(e.n2)] - m.x0[static_cast<size_t>(e.n1)]).norm();
      if (!(L > 0.0)) c.fail("bar element " + std::to_string(e.id) + " has zero length");
      if (material_of(e.part, c).plastic)
        c.fail("part " + std::to_string(e.part) + ": plasticity is in the solids (3D and axisymmetric), not in 1D bars");
      const double half = 0.5 * material_of(e.part, c).rho * m.parts[e.part].bar_area * L;
      m.mass[static_cast<size_t>(e.n1)] += half;
      m.mass[static_cast<size_t>(e.n2)] += half;
      m.bars.push_back(e);
    }
    axisymmetric_elements();
  }

  // A node on the axis pressed against an elastic axisymmetric surface is a
  // point load on a body of revolution: the elastic solution under it is
  // singular, so the surface's nodes there run away. (Against a rigid part
  // it is fine: a bar's end on a rigid piston.)
  void warn_point_loads_on_the_axis() {
    if (m.axis.empty()) return;
    std::set<int> elastic;
    for (const auto& e : m.axis)
      if (!m.materials.at(m.parts.at(e.part).material).rigid) elastic.insert(e.n, e.n + 4);
    for (const auto& c : m.contacts) {
      if (!c.slave_nodes) continue;
      bool elastic_master = false;
      for (const auto& seg : m.segment_sets.at(c.master_set))
        for (int k = 0; k < seg.corners(); ++k) elastic_master = elastic_master || elastic.count(seg.n[k]) > 0;
      if (!elastic_master) continue;
      for (int id : m.node_sets.at(c.slave_set))
        if (m.x0[static_cast<size_t>(m.index_of(id, c.where))].x() == 0.0)
          warn(c.where, "node " + std::to_string(id) +
                            " lies on the axis and presses on an elastic axisymmetric surface: a point load on a body "
                            "of revolution, which the surface cannot carry (its solution is singular); make that part "
                            "rigid, or let a ring of nodes (or a 2D part) carry the load");
    }
  }

  // A 2D node on the axis of symmetry: r = 0 exactly, as LS-DYNA's 2D decks
  // place it.
  static bool on_axis(const Vec3& p) { return p.x() == 0.0; }

  // Nodes of axisymmetric elements move in the x–y plane only; those on the
  // axis do not move radially.
  void constrain_axisymmetric_nodes() {
    for (const auto& e : m.axis)
      for (int k = 0; k < 4; ++k) {
        const size_t i = static_cast<size_t>(e.n[k]);
        m.fixed[i][2] = true;
        if (on_axis(m.x0[i])) m.fixed[i][0] = true;
      }
  }

  void axisymmetric_elements() {
    for (const Card& c : shell_cards) {
      AxiElement e;
      e.id = static_cast<int>(c.integer(0, "EID"));
      e.part = static_cast<int>(c.integer(1, "PID"));
      const Material& mat = material_of(e.part, c);
      auto sec = sections.find(m.parts[e.part].section);
      if (sec == sections.end() || sec->second.first != 15)
        c.fail("part " + std::to_string(e.part) + " needs a *SECTION_SHELL with ELFORM 15 or 14 (axisymmetric solid)");
      std::vector<int> ids;
      for (size_t k = 2; k < c.fields.size() && ids.size() < 4; ++k)
        if (!c.fields[k].empty() && c.integer(k, "N") != 0) ids.push_back(static_cast<int>(c.integer(k, "N")));
      if (ids.size() == 3) ids.push_back(ids[2]);  // a triangle: N4 = N3
      if (ids.size() != 4) c.fail("an axisymmetric element needs 3 or 4 nodes, got " + std::to_string(ids.size()));
      Mat42 x;
      for (int k = 0; k < 4; ++k) {
        e.n[k] = m.index_of(ids[static_cast<size_t>(k)], c.where);
        const Vec3& p = m.x0[static_cast<size_t>(e.n[k])];
        if (p.x() < 0.0 || p.z() != 0.0)
          c.fail("node " + std::to_string(ids[static_cast<size_t>(k)]) +
                 " of an axisymmetric element must lie in the x-y plane with x (the radius) >= 0 and z = 0");
        x(k, 0) = p.x(), x(k, 1) = p.y();
      }
      Axi4Geometry g;
      if (!axi4_geometry(x, g))
        c.fail("axisymmetric element " + std::to_string(e.id) + " has area " + std::to_string(g.area) +
               " m²: its nodes must run counter-clockwise in the x-y plane (x the radius, y the axis)");
      const Eigen::Vector4d mass = axi4_lumped_masses(x, mat.rho);
      for (int k = 0; k < 4; ++k) m.mass[static_cast<size_t>(e.n[k])] += mass(k);
      m.axis.push_back(e);
    }
  }

  void discrete(const Card& c) {
    DiscreteElement d;
    d.where = c.where;
    d.id = static_cast<int>(c.integer(0, "EID"));
    int pid = static_cast<int>(c.integer(1, "PID"));
    d.n1 = m.index_of(static_cast<int>(c.integer(2, "N1")), c.where);
    d.n2 = m.index_of(static_cast<int>(c.integer(3, "N2")), c.where);
    double scale = c.real_or(5, "S", 1.0);
    if (scale == 0.0) scale = 1.0;  // LS-DYNA: S = 0 means 1
    d.offset = c.real_or(7, "OFFSET", 0.0);
    auto p = m.parts.find(pid);
    if (p == m.parts.end()) c.fail("part " + std::to_string(pid) + " is not defined in *PART");
    auto mat = spring_mats.find(p->second.material);
    if (mat == spring_mats.end())
      c.fail("part " + std::to_string(pid) + " has material " + std::to_string(p->second.material) +
             ", which is not a *MAT_SPRING_ELASTIC or *MAT_DAMPER_VISCOUS");
    d.k = scale * mat->second.first;
    d.c = scale * mat->second.second;
    d.length0 = (m.x0[static_cast<size_t>(d.n2)] - m.x0[static_cast<size_t>(d.n1)]).norm();
    if (d.length0 <= 0.0) c.fail("discrete element " + std::to_string(d.id) + " has zero length: its direction is undefined");
    m.discretes.push_back(d);
  }

  // NID|NSID DOF VAD LCID SF VID DEATH BIRTH.
  void prescribed_motion(const Card& c, bool is_set, bool rigid = false) {
    PrescribedMotion p;
    p.where = c.where;
    const int id = static_cast<int>(c.integer(0, rigid ? "PID" : is_set ? "NSID" : "NID"));
    if (rigid) {
      auto part = m.parts.find(id);
      if (part == m.parts.end()) c.fail("part " + std::to_string(id) + " is not defined");
      if (!m.materials.at(part->second.material).rigid)
        c.fail("part " + std::to_string(id) + " is not of a *MAT_RIGID material: prescribe its nodes instead");
      p.rigid_part = id;
    } else {
      p.nodes = is_set ? nodes_of_set(id, c) : std::vector<int>{m.index_of(id, c.where)};
    }
    const long dof = c.integer(1, "DOF");
    if (dof < 1 || dof > 3)
      c.fail("DOF " + std::to_string(dof) + ": 1, 2 or 3 (x, y, z translation) are supported; rotations and "
             "directions by vector are not");
    p.dof = static_cast<int>(dof - 1);
    const long vad = c.integer_or(2, "VAD", 0);
    if (vad < 0 || vad > 2) c.fail("VAD " + std::to_string(vad) + ": 0 velocity, 1 acceleration or 2 displacement");
    p.vad = static_cast<int>(vad);
    p.curve_id = static_cast<int>(c.integer(3, "LCID"));
    if (!m.curves.count(p.curve_id)) c.fail("LCID " + std::to_string(p.curve_id) + " is not defined by a *DEFINE_CURVE");
    p.sf = c.real_or(4, "SF", 1.0);
    if (p.sf == 0.0) p.sf = 1.0;  // LS-DYNA: 0 means 1
    if (c.integer_or(5, "VID", 0) != 0) c.fail("VID (a direction vector) is not supported: use DOF 1, 2 or 3");
    p.death = c.real_or(6, "DEATH", 0.0);
    if (p.death == 0.0) p.death = 1e28;
    p.birth = c.real_or(7, "BIRTH", 0.0);
    if (!(p.birth < p.death)) c.fail("BIRTH must come before DEATH");
    for (int i : p.nodes)
      if (m.fixed[static_cast<size_t>(i)][p.dof])
        c.fail("node " + std::to_string(m.node_ids[static_cast<size_t>(i)]) + " has that DOF fixed by an SPC as well");
    m.prescribed.push_back(std::move(p));
  }

  void spc(const Card& c, const std::vector<int>& nodes) {
    for (int i : nodes)
      for (int k = 0; k < 3; ++k)
        if (c.integer_or(static_cast<size_t>(2 + k), "DOF", 0) != 0) m.fixed[static_cast<size_t>(i)][k] = true;
  }

  // A *PART (or *PART_INERTIA): its title card and its PID SECID MID card.
  const Part& part(const Card& title, const Card& raw) {
    Card c = fields_of(raw, kW10);
    Part p;
    p.title = config::trim(title.text);
    p.id = static_cast<int>(c.integer(0, "PID"));
    p.section = static_cast<int>(c.integer_or(1, "SECID", 0));
    p.material = static_cast<int>(c.integer_or(2, "MID", 0));
    p.where = c.where;
    if (m.parts.count(p.id)) c.fail("part " + std::to_string(p.id) + " defined twice");
    return m.parts[p.id] = p;
  }

  // SIGY and ETAN of the plastic materials' first card.
  static void plastic_constants(Material& mat, const Card& c) {
    mat.plastic = true;
    mat.yield = c.real(4, "SIGY");
    const double etan = c.real_or(5, "ETAN", 0.0);
    if (!(mat.yield > 0.0)) c.fail("SIGY must be positive");
    if (etan < 0.0 || etan >= mat.E) c.fail("ETAN must be at least 0 and below E");
    mat.plastic_modulus = mat.E * etan / (mat.E - etan);
  }

  // MID RO E PR of *MAT_ELASTIC and *MAT_RIGID's first card.
  static Material elastic_constants(const Card& c) {
    Material mat;
    mat.id = static_cast<int>(c.integer(0, "MID"));
    mat.rho = c.real(1, "RO");
    mat.E = c.real(2, "E");
    mat.nu = c.real_or(3, "PR", 0.0);
    mat.where = c.where;
    if (!(mat.rho > 0.0) || !(mat.E > 0.0)) c.fail("RO and E must be positive");
    if (mat.nu < 0.0 || mat.nu >= 0.5) c.fail("PR must be in [0, 0.5)");
    return mat;
  }

  // *MAT_RIGID's CON1/CON2 codes: 0 none, 1 x, 2 y, 3 z, 4 x+y, 5 y+z, 6 z+x, 7 all.
  static Eigen::Matrix<bool, 3, 1> constraint_code(const Card& c, size_t i, const char* name) {
    const long code = static_cast<long>(c.real_or(i, name, 0.0));
    if (code < 0 || code > 7) c.fail(std::string(name) + " must be 0..7, got " + std::to_string(code));
    return {code == 1 || code == 4 || code == 6 || code == 7, code == 2 || code == 4 || code == 5 || code == 7,
            code == 3 || code == 5 || code == 6 || code == 7};
  }

  // *PART_INERTIA: a *PART (title, PID SECID MID) followed by XC YC ZC TM
  // IRCS NODEID, IXX IXY IXZ IYY IYZ IZZ (the tensor's components in global
  // axes, about the centre of mass) and VTX VTY VTZ VRX VRY VRZ.
  void part_inertia(const Block& b) {
    if (b.cards.size() != 5)
      b.fail("*PART_INERTIA needs five cards: title; PID SECID MID; XC YC ZC TM IRCS NODEID; IXX IXY IXZ IYY IYZ IZZ; "
             "VTX VTY VTZ VRX VRY VRZ");
    const Part& p = part(b.cards[0], b.cards[1]);
    Card c3 = fields_of(b.cards[2], kW10), c4 = fields_of(b.cards[3], kW10), c5 = fields_of(b.cards[4], kW10);
    RigidBody rb;
    rb.inertia_given = true;
    rb.com = Vec3(c3.real_or(0, "XC", 0.0), c3.real_or(1, "YC", 0.0), c3.real_or(2, "ZC", 0.0));
    rb.mass = c3.real(3, "TM");
    if (!(rb.mass > 0.0)) c3.fail("TM must be positive");
    if (c3.integer_or(4, "IRCS", 0) != 0) c3.fail("only IRCS = 0 (inertia tensor in global axes) is supported");
    const long com_node = c3.integer_or(5, "NODEID", 0);
    if (com_node != 0) inertia_com_node[p.id] = {static_cast<int>(com_node), c3.where};
    const double ixx = c4.real(0, "IXX"), ixy = c4.real_or(1, "IXY", 0.0), ixz = c4.real_or(2, "IXZ", 0.0),
                 iyy = c4.real(3, "IYY"), iyz = c4.real_or(4, "IYZ", 0.0), izz = c4.real(5, "IZZ");
    rb.inertia << ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(rb.inertia);
    if (eig.eigenvalues().minCoeff() < -1e-12 * eig.eigenvalues().maxCoeff())
      c4.fail("the inertia tensor is not positive semi-definite");
    rb.v0 = Vec3(c5.real_or(0, "VTX", 0.0), c5.real_or(1, "VTY", 0.0), c5.real_or(2, "VTZ", 0.0));
    rb.omega0 = Vec3(c5.real_or(3, "VRX", 0.0), c5.real_or(4, "VRY", 0.0), c5.real_or(5, "VRZ", 0.0));
    rb.where = p.where;
    inertias[p.id] = rb;
  }

  void rigid_bodies() {
    std::set<int> in_body;
    auto add_body = [&](RigidBody rb, const std::vector<int>& nodes, const Card* c) {
      for (int idx : nodes) {
        if (!in_body.insert(idx).second) {
          std::string msg = "node " + std::to_string(m.node_ids[static_cast<size_t>(idx)]) + " belongs to two rigid bodies";
          if (c) c->fail(msg);
          throw InputError(rb.where, msg);
        }
        rb.nodes.push_back(idx);
        rb.mass += m.mass[static_cast<size_t>(idx)];
      }
      if (!(rb.mass > 0.0) && !rb.inertia_given)
        throw InputError(rb.where, "rigid body " + std::to_string(rb.id) + " has no mass");
      m.rigid_bodies.push_back(rb);
    };
    for (const NodalRigidBodyCards& r : rigid_cards) {
      const Card& c = r.card;
      RigidBody rb;
      rb.where = c.where;
      rb.id = static_cast<int>(c.integer(0, "PID"));
      rb.fixed_translation = r.fixed_translation;
      rb.fixed_rotation = r.fixed_rotation;
      add_body(rb, nodes_of_set(static_cast<int>(c.integer(2, "NSID")), c), &c);
    }
    auto rigid_part = [&](long pid, const Card& c, const char* name) {
      auto part = m.parts.find(static_cast<int>(pid));
      if (part == m.parts.end()) c.fail(std::string(name) + " " + std::to_string(pid) + " is not a *PART");
      auto mat = m.materials.find(part->second.material);
      if (mat == m.materials.end() || !mat->second.rigid)
        c.fail(std::string(name) + " " + std::to_string(pid) + " is not of a *MAT_RIGID material");
      return static_cast<int>(pid);
    };
    // *CONSTRAINED_RIGID_BODIES: each constrained part joins its lead's body
    // (a lead that is itself constrained hands it on to its own lead).
    std::map<int, int> lead_of;
    for (const Card& c : merge_cards) {
      const int lead = rigid_part(c.integer(0, "PIDL"), c, "PIDL");
      const int follower = rigid_part(c.integer(1, "PIDC"), c, "PIDC");
      if (c.integer_or(2, "IFLAG", 0) != 0) c.fail("IFLAG other than 0 (the merged body's inertia from all its parts) is not supported");
      if (lead == follower || lead_of.count(follower)) c.fail("part " + std::to_string(follower) + " is constrained twice or to itself");
      if (inertias.count(lead) || inertias.count(follower))
        c.fail("a *PART_INERTIA part cannot be merged: its given inertia would not hold the other part's");
      lead_of[follower] = lead;
    }
    auto final_lead = [&](int pid) {
      for (size_t hops = 0; lead_of.count(pid); ++hops) {
        if (hops > lead_of.size()) throw InputError(merge_cards.front().where, "*CONSTRAINED_RIGID_BODIES form a cycle");
        pid = lead_of.at(pid);
      }
      return pid;
    };
    std::map<int, std::vector<int>> extra;  // lead part → nodes it gains
    for (const auto& [follower, lead] : lead_of) {
      const std::vector<int> nodes = nodes_of_parts({follower});
      auto& to = extra[final_lead(follower)];
      to.insert(to.end(), nodes.begin(), nodes.end());
    }
    for (const auto& [c, is_set] : extra_node_cards) {
      const int pid = rigid_part(c.integer(0, "PID"), c, "PID");
      if (lead_of.count(pid)) c.fail("part " + std::to_string(pid) + " is merged into another (*CONSTRAINED_RIGID_BODIES): name the lead part");
      auto& to = extra[pid];
      if (is_set) {
        const std::vector<int> nodes = nodes_of_set(static_cast<int>(c.integer(1, "NSID")), c);
        to.insert(to.end(), nodes.begin(), nodes.end());
      } else {
        to.push_back(m.index_of(static_cast<int>(c.integer(1, "NID")), c.where));
      }
    }
    // *MAT_RIGID parts: their element nodes (and the nodes they gained) move as one body.
    for (const auto& [pid, part] : m.parts) {
      auto mat = m.materials.find(part.material);
      auto given = inertias.find(pid);
      if (mat == m.materials.end() || !mat->second.rigid) {
        if (given != inertias.end())
          throw InputError(given->second.where, "*PART_INERTIA part " + std::to_string(pid) + " is not of a *MAT_RIGID material");
        continue;
      }
      if (lead_of.count(pid)) continue;  // moves with its lead
      RigidBody rb = given != inertias.end() ? given->second : RigidBody();
      rb.id = pid;
      rb.where = part.where;
      rb.fixed_translation = mat->second.rigid_fixed_translation;
      rb.fixed_rotation = mat->second.rigid_fixed_rotation;
      if (auto cn = inertia_com_node.find(pid); cn != inertia_com_node.end())
        rb.com = m.x0[static_cast<size_t>(m.index_of(cn->second.first, cn->second.second))];
      const double given_mass = rb.mass;
      rb.mass = 0.0;
      std::vector<int> nodes = nodes_of_parts({pid});
      if (auto e = extra.find(pid); e != extra.end()) {
        std::set<int> all(nodes.begin(), nodes.end());
        all.insert(e->second.begin(), e->second.end());
        nodes.assign(all.begin(), all.end());
      }
      add_body(rb, nodes, nullptr);
      if (rb.inertia_given) m.rigid_bodies.back().mass = given_mass;
    }
  }
};

// NaN and Inf in any field, read or not: a field a keyword skips today may be
// read tomorrow, and a deck holding one is broken either way. Titles are text.
void refuse_non_finite(const Block& b) {
  if (b.keyword == "*TITLE" || b.keyword == "*KEYWORD" || b.keyword == "*COMMENT") return;
  for (size_t i = 0; i < b.cards.size(); ++i) {
    if (b.keyword == "*PART" && i % 2 == 0) continue;  // the part's title card
    const Card& c = b.cards[i];
    std::vector<std::string> tokens = c.fields;
    if (!c.comma_separated) {
      std::istringstream in(c.text);
      for (std::string t; in >> t;) tokens.push_back(t);
    }
    for (size_t k = 0; k < tokens.size(); ++k) {
      const std::string& t = tokens[k];
      if (t.empty() || !(std::isdigit(static_cast<unsigned char>(t[0])) || t[0] == '+' || t[0] == '-' || t[0] == '.' ||
                         t[0] == 'n' || t[0] == 'N' || t[0] == 'i' || t[0] == 'I'))
        continue;
      char* end = nullptr;
      const double v = std::strtod(t.c_str(), &end);
      if (end != t.c_str() && *end == '\0' && !std::isfinite(v))
        c.fail("field " + std::to_string(k + 1) + " of " + b.keyword + ": '" + t +
               "' is not a finite number (NaN and Inf are refused in every field, read or not)");
    }
  }
}

}  // namespace

Model parse_deck(const std::string& text, const std::string& name, DeckWarnings* warnings) {
  Model m;
  m.source = name;
  Reader r(m, warnings);
  auto blocks = config::parse_keyword_text(text, name, true, true);
  if (!blocks.empty() && blocks.front().keyword != "*KEYWORD" && warnings)
    warnings->messages.push_back(name + ":1: warning: the deck does not start with *KEYWORD");
  // LS-DYNA stops reading at *END.
  if (const auto end = std::find_if(blocks.begin(), blocks.end(), [](const Block& b) { return b.keyword == "*END"; });
      end != blocks.end())
    blocks.erase(end, blocks.end());
  // Every block is read even after one failed, so a deck's errors come in
  // one run (up to kMaxDeckErrors), not one per run. The cross-references
  // (finish) are only resolved for a deck whose blocks all read: after a
  // failed block they would report its consequences, not new errors.
  std::vector<InputError> errors;
  for (const Block& b : normalise_blocks(std::move(blocks))) {
    try {
      r.block(b);           // a field it reads names itself ("VZ: expected a finite number")
      refuse_non_finite(b);  // then the fields it skipped
    } catch (const InputError& e) {
      errors.push_back(e);
      if (errors.size() == kMaxDeckErrors) break;
    }
  }
  if (!errors.empty()) {
    const InputError& first = errors.front();
    std::string all = std::string(first.what()).substr(first.where().str().size() + 2);
    for (size_t i = 1; i < errors.size(); ++i) all += std::string("\n") + errors[i].what();
    if (errors.size() > 1)
      all += "\n(" + std::to_string(errors.size()) + (errors.size() == kMaxDeckErrors ? " errors or more" : " errors") +
             " in " + name + ")";
    throw InputError(first.where(), all);
  }
  r.finish(name);
  return m;
}

Model read_deck(const std::string& path, DeckWarnings* warnings) {
  return parse_deck(config::read_text_file(path, "deck"), path, warnings);
}

std::string deck_keyword_coverage() {
  std::ostringstream s;
  s << "# LS-DYNA keywords fe_server reads\n\n"
       "Generated by `fe_server --keywords` from the reader's own table (fe_server/src/input/deck_reader.cpp); a test "
       "checks that this page is its output. A field a keyword's reader does not implement is refused at its line, "
       "or, with `--approximate`, substituted and listed in the results.\n\n"
       "| keyword | what fe_server makes of it |\n|---|---|\n";
  for (const Reader::Keyword& k : Reader::keywords()) {
    s << "| ";
    for (size_t i = 0; i < k.names.size(); ++i) s << (i ? ", " : "") << "`" << k.names[i] << "`";
    s << " | " << k.what << " |\n";
  }
  s << "\nAlso: `*KEYWORD`, `*END` (ends its own file), `*COMMENT`, `*INCLUDE`, `*INCLUDE_PATH`, "
       "`_TITLE` and `_ID` forms, long format.\n\n"
       "Ignored with a warning, because fe_server writes its own results: the other output requests";
  const char* sep = ": ";
  for (const std::string& k : Reader::database_keywords())
    if (!Reader::keyword_index().count(k)) s << sep << "`" << k << "`", sep = ", ";
  s << "; `*CONTROL_OUTPUT`, `*CONTROL_ENERGY`, `*CONTROL_CPU`; and any other `*CONTROL_` card that holds only "
       "LS-DYNA's defaults: blanks, zeros, and these values where LS-DYNA's manual gives a default other than 0";
  sep = ": ";
  for (const Reader::ControlDefault& d : Reader::control_defaults())
    s << sep << "`" << d.keyword << "` " << d.name << " " << Reader::short_number(d.value), sep = ", ";
  s << ".\n\nIgnored with a note, because they set how LS-DYNA runs and never what it computes: `*CONTROL_PARALLEL`, "
       "`*CONTROL_MPP_IO_...`, `*CONTROL_MPP_DECOMPOSITION_...`.\n\n"
       "Refused with the reason (any other keyword is refused at its line too):\n\n"
       "| keyword | why |\n|---|---|\n";
  for (const auto& [prefix, why] : Reader::refusals()) {
    const std::string p = prefix;
    s << "| `" << p << (p.back() == '_' ? "...`" : "`") << " | " << why << " |\n";
  }
  s << "| `*CASE...` | load cases: their contents would apply to every case; run each case as its own deck |\n";
  return s.str();
}

}  // namespace fe
