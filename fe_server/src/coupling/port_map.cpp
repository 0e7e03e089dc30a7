#include "coupling/port_map.hpp"

#include <cmath>
#include <cstdio>

namespace fe {

using config::Quantity;

PortMap::PortMap(const config::PortTable& table, CavityPressureLoad& load, MechanicalLoad& mech)
    : table_(table), load_(load), mech_(mech) {
  for (const auto& v : table.to_fe) {
    const int m = mech.slot_of_port(v.port_id);
    in_mech_.push_back(m >= 0);
    if (m >= 0) {
      if (v.quantity != Quantity::Force)
        throw config::InputError(v.where, "a mechanical port takes a force from the host, not " +
                                              std::string(config::long_name(v.quantity)));
      in_slot_.push_back(m);
      continue;
    }
    int slot = load.slot_of_port(v.port_id);
    const bool ok = slot >= 0 && (v.quantity == Quantity::Pressure || v.quantity == Quantity::Wave ||
                                  v.quantity == Quantity::Impedance);
    if (!ok)
      throw config::InputError(v.where, std::string("fe_server cannot apply ") + config::long_name(v.quantity) +
                                            " at port " + v.port_label +
                                            " yet: hydraulic ports take pressure, or wave and impedance");
    in_slot_.push_back(slot);
  }
  for (const auto& v : table.to_host) {
    const int m = mech.slot_of_port(v.port_id);
    out_mech_.push_back(m >= 0);
    if (m >= 0) {
      out_slot_.push_back(m);
      continue;
    }
    int slot = load.slot_of_port(v.port_id);
    bool ok = slot >= 0 && (v.quantity == Quantity::Flow || v.quantity == Quantity::Displacement ||
                            v.quantity == Quantity::Velocity || v.quantity == Quantity::Pressure);
    if (!ok)
      throw config::InputError(v.where, std::string("fe_server cannot return ") + config::long_name(v.quantity) +
                                            " at port " + v.port_label +
                                            " yet: hydraulic ports return flow, pressure, displacement and velocity");
    out_slot_.push_back(slot);
  }
  const size_t slots = load.slot_count();
  wave_.assign(slots, 0.0);
  impedance_.assign(slots, 0.0);
  tlm_.assign(slots, 0);
  zc_sent_.assign(slots, 0);
  for (size_t i = 0; i < table.to_fe.size(); ++i)
    if (!in_mech_[i] && table.to_fe[i].quantity == Quantity::Impedance) zc_sent_[static_cast<size_t>(in_slot_[i])] = 1;
  flow_sum_.assign(slots, 0.0);
  pressure_sum_.assign(slots, 0.0);
}

void PortMap::apply_inputs(const std::vector<double>& in) {
  std::fill(tlm_.begin(), tlm_.end(), 0);
  for (size_t i = 0; i < in.size(); ++i) {
    if (in_mech_[i]) {
      mech_.set_force(in_slot_[i], in[i]);
      continue;
    }
    const size_t slot = static_cast<size_t>(in_slot_[i]);
    switch (table_.to_fe[i].quantity) {
      case Quantity::Pressure: load_.set_pressure(in_slot_[i], in[i]); break;
      case Quantity::Wave: wave_[slot] = in[i], tlm_[slot] = 1; break;
      case Quantity::Impedance:  // TLM: with the wave; pressure mode: the stability check's only
        impedance_[slot] = in[i];
        if (table_.mode == config::CouplingMode::Tlm) tlm_[slot] = 1;
        break;
      default: break;
    }
  }
  for (size_t slot = 0; slot < tlm_.size(); ++slot)
    if (tlm_[slot]) load_.set_wave(static_cast<int>(slot), wave_[slot], impedance_[slot]);
  std::fill(flow_sum_.begin(), flow_sum_.end(), 0.0);
  std::fill(pressure_sum_.begin(), pressure_sum_.end(), 0.0);
  substeps_ = 0.0;
}

void PortMap::set_coupling_guard(const std::vector<PortStability>& ports, double T, bool allow) {
  guard_.assign(load_.slot_count(), Guard{});
  guard_T_ = T;
  if (allow) return;
  for (const auto& p : ports) {
    const int slot = load_.slot_of_port(p.port_id);
    if (slot < 0 || !(p.mass > 0.0) || !(p.area > 0.0)) continue;
    guard_[static_cast<size_t>(slot)] = Guard{p.label, p.mass, p.area, -1.0};
  }
}

std::string PortMap::check_coupling() {
  const bool pressure = table_.mode == config::CouplingMode::Pressure;
  for (size_t slot = 0; slot < guard_.size(); ++slot) {
    Guard& g = guard_[slot];
    // A pressure port is checked when the table sends the host's Zc and the
    // host gave one (an importer without chambers, FMPy, leaves it 0).
    if (!(pressure ? zc_sent_[slot] && impedance_[slot] > 0.0 : tlm_[slot]) || g.mass == 0.0 ||
        impedance_[slot] == g.checked_zc)
      continue;
    g.checked_zc = impedance_[slot];
    const double zc = impedance_[slot], T = guard_T_;
    const double omega_t = g.area * std::sqrt(std::max(zc, 0.0) * T / g.mass);
    if (pressure) {
      if (omega_t <= kMaxPressureOmegaT) continue;
      char msg[900];
      std::snprintf(msg, sizeof msg,
                    "pressure-coupled port %s is beyond the stability limit of pressure coupling: Zc = %.4g Pa·s/m³ "
                    "from the host on %.4g kg behind %.4g cm² gives ω·T = %.3g at the coupling step %g s, above %g "
                    "(the held pressure diverges from ω·T = 1.33–1.46 on the stability map). Couple it in TLM mode "
                    "(mode tlm, stable for any chamber), or lower the coupling step to at most %.3g s, or enlarge the "
                    "chamber %.3g times (Zc = β·T/V); fe_server --allow-coarse-coupling runs it anyway",
                    g.label.c_str(), zc, g.mass, g.area * 1e4, omega_t, T, kMaxPressureOmegaT,
                    T * kMaxPressureOmegaT / omega_t, omega_t * omega_t / (kMaxPressureOmegaT * kMaxPressureOmegaT));
      return msg;
    }
    if (omega_t <= max_tlm_omega_t()) continue;
    // A chamber's Zc = β·T/V grows with T, so ω·T is proportional to T: the
    // largest step that passes, and the chamber that would at this step.
    const double t_max = T * max_tlm_omega_t() / omega_t;
    char msg[900];
    std::snprintf(msg, sizeof msg,
                  "TLM port %s is coupled far too coarsely for its chamber: Zc = %.4g Pa·s/m³ from the host on %.4g kg "
                  "behind %.4g cm² gives ω·T = %.3g at the coupling step %g s, beyond %.2f, where the frequency error "
                  "estimate k·(ω·T)² (k = %g) reaches %.0f %%. Lower the coupling step (timestep in the port table and "
                  "the host's) to at most %.3g s, or enlarge the chamber %.3g times (Zc = β·T/V); "
                  "fe_server --allow-coarse-coupling runs it anyway",
                  g.label.c_str(), zc, g.mass, g.area * 1e4, omega_t, T, max_tlm_omega_t(), kTlmErrorPerOmegaT2,
                  100.0 * kMaxTlmFrequencyError, t_max, (omega_t / max_tlm_omega_t()) * (omega_t / max_tlm_omega_t()));
    return msg;
  }
  return "";
}

void PortMap::accumulate(const Solver& s) {
  // A time average: a step shortened by the model's stable step weighs its
  // share (exactly 1 at the coupling step over its subcycles).
  const double w = s.dt() / s.dt_cap();
  for (size_t slot = 0; slot < flow_sum_.size(); ++slot) {
    flow_sum_[slot] += w * load_.step_flow(static_cast<int>(slot), s.v_live());
    pressure_sum_[slot] += w * load_.pressure(static_cast<int>(slot));
  }
  substeps_ += w;
}

void PortMap::measure_outputs(const Solver& s, std::vector<double>& out) {
  out.resize(table_.to_host.size());
  const double n = substeps_ > 0.0 ? substeps_ : 1.0;
  for (size_t i = 0; i < out.size(); ++i) {
    const int slot = out_slot_[i];
    if (out_mech_[i]) {
      switch (table_.to_host[i].quantity) {
        case Quantity::Displacement: out[i] = mech_.displacement(slot, s.x_live()); break;
        case Quantity::Velocity: out[i] = mech_.velocity(slot, s.v_live()); break;
        case Quantity::Force: out[i] = mech_.force(slot); break;
        default: out[i] = 0.0;
      }
      continue;
    }
    switch (table_.to_host[i].quantity) {
      case Quantity::Flow: out[i] = flow_sum_[static_cast<size_t>(slot)] / n; break;
      case Quantity::Pressure: out[i] = pressure_sum_[static_cast<size_t>(slot)] / n; break;
      case Quantity::Displacement: out[i] = load_.displacement(slot, s.x_live()); break;
      case Quantity::Velocity: {
        const double a = load_.area(slot);
        out[i] = a > 0.0 ? load_.flow(slot, s.v_live()) / a : 0.0;
        break;
      }
      default: out[i] = 0.0;
    }
  }
}

}  // namespace fe
