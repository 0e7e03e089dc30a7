// The hammer scene's model (scenes/hammer/model.tlm) with its one FMU "fe"
// split into two on one fe_server session: "fe_p" (cavities, piston, tool:
// two_fmus/piston.cfg) and "fe_v" (pilots, spool: two_fmus/valve.cfg).
#pragma once

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

// source: the scene's folder; built: where its FMUs were generated;
// pressure: the pressure-coupled pair (two_fmus/*_pressure.cfg).
inline std::string hammer_model_with_two_fmus(const std::string& source, const std::string& built, bool pressure = false) {
  const std::string p = pressure ? "_p" : "";
  std::stringstream buf;
  buf << std::ifstream(source + "/model.tlm").rdbuf();
  std::string text = buf.str();
  auto replace_all = [&](const std::string& from, const std::string& to) {
    size_t n = 0;
    for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()), ++n)
      text.replace(at, from.size(), to);
    return n;
  };
  if (replace_all("fe,          FmuQ",
                  "fe_p, FmuQ, fmu=" + built + "/hammer_piston" + p + ".fmu\nfe_v, FmuQ, fmu=" + built + "/hammer_valve" + p + ".fmu") != 1)
    throw std::runtime_error("the hammer model no longer has its one FmuQ line 'fe,          FmuQ'");
  for (const char* label : {"cavA", "cavB", "piston", "tool"}) replace_all(std::string("fe.") + label, std::string("fe_p.") + label);
  for (const char* label : {"pilot_s", "pilot_c", "spool"}) replace_all(std::string("fe.") + label, std::string("fe_v.") + label);
  if (text.find(" fe.") != std::string::npos) throw std::runtime_error("the hammer model has a port of 'fe' not split");
  return text;
}
