#include "fmu_importer.hpp"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>

#include "config/keyword_reader.hpp"
#include "socketlib/socketlib.h"

#include <dlfcn.h>
#include <zip.h>

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

namespace tlm {

namespace fs = std::filesystem;

const FmuScalar* ModelDescription::find(const std::string& name) const {
  for (const auto& v : variables)
    if (v.name == name) return &v;
  return nullptr;
}

namespace {

std::string decode_entities(const std::string& s) {
  static const std::pair<const char*, char> kEntities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    bool done = false;
    if (s[i] == '&')
      for (const auto& [ent, ch] : kEntities)
        if (s.compare(i, std::strlen(ent), ent) == 0) {
          out += ch;
          i += std::strlen(ent) - 1;
          done = true;
          break;
        }
    if (!done) out += s[i];
  }
  return out;
}

struct Tag {
  std::string name;  // "/Name" for a closing tag
  std::map<std::string, std::string> attrs;
};

// Split XML into its tags (text content is not needed here), skipping the
// declaration, comments and processing instructions.
std::vector<Tag> scan_tags(const std::string& xml, const std::string& source) {
  std::vector<Tag> tags;
  size_t i = 0;
  while ((i = xml.find('<', i)) != std::string::npos) {
    if (xml.compare(i, 4, "<!--") == 0) {
      size_t e = xml.find("-->", i);
      if (e == std::string::npos) throw std::runtime_error(source + ": unterminated comment");
      i = e + 3;
      continue;
    }
    if (xml.compare(i, 2, "<?") == 0) {
      size_t e = xml.find("?>", i);
      if (e == std::string::npos) throw std::runtime_error(source + ": unterminated declaration");
      i = e + 2;
      continue;
    }
    size_t j = i + 1;
    Tag t;
    while (j < xml.size() && !std::isspace(static_cast<unsigned char>(xml[j])) && xml[j] != '>' && xml[j] != '/')
      ++j;
    if (xml[i + 1] == '/') {  // closing tag
      size_t e = xml.find('>', i);
      if (e == std::string::npos) throw std::runtime_error(source + ": unterminated tag");
      t.name = xml.substr(i + 1, e - i - 1);
      tags.push_back(t);
      i = e + 1;
      continue;
    }
    t.name = xml.substr(i + 1, j - i - 1);
    for (;;) {
      while (j < xml.size() && std::isspace(static_cast<unsigned char>(xml[j]))) ++j;
      if (j >= xml.size()) throw std::runtime_error(source + ": unterminated tag <" + t.name);
      if (xml[j] == '>' || xml[j] == '/') break;
      size_t eq = xml.find('=', j);
      if (eq == std::string::npos) throw std::runtime_error(source + ": attribute without value in <" + t.name);
      std::string key = xml.substr(j, eq - j);
      while (!key.empty() && std::isspace(static_cast<unsigned char>(key.back()))) key.pop_back();
      size_t q = eq + 1;
      while (q < xml.size() && std::isspace(static_cast<unsigned char>(xml[q]))) ++q;
      if (q >= xml.size() || (xml[q] != '"' && xml[q] != '\''))
        throw std::runtime_error(source + ": unquoted attribute " + key + " in <" + t.name);
      size_t end = xml.find(xml[q], q + 1);
      if (end == std::string::npos) throw std::runtime_error(source + ": unterminated attribute " + key);
      t.attrs[key] = decode_entities(xml.substr(q + 1, end - q - 1));
      j = end + 1;
    }
    size_t e = xml.find('>', j);
    if (e == std::string::npos) throw std::runtime_error(source + ": unterminated tag <" + t.name);
    bool self_closing = xml[j] == '/';
    tags.push_back(t);
    if (self_closing) tags.push_back(Tag{"/" + t.name, {}});
    i = e + 1;
  }
  return tags;
}

// The FMU's logger callback: C variadic, as the standard defines it.
extern "C" void pcs_fmu_logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                               fmi2String category, fmi2String message, ...) {
  char text[2048];
  va_list args;
  va_start(args, message);
  std::vsnprintf(text, sizeof text, message ? message : "", args);
  va_end(args);
  auto* log = static_cast<FmuInstance::Log*>(env);
  if (log && (status == fmi2Error || status == fmi2Fatal)) log->last_error = text;
  if (status >= fmi2Warning || (log && log->verbose))
    std::cerr << "[" << (instance ? instance : "fmu") << "] " << (category ? category : "") << ": " << text << "\n";
}

}  // namespace

ModelDescription parse_model_description(const std::string& xml, const std::string& source) {
  ModelDescription md;
  std::map<std::string, std::string> type_units;  // SimpleType name → its Real unit
  auto tags = scan_tags(xml, source);
  bool root = false;
  for (size_t i = 0; i < tags.size(); ++i) {
    const Tag& t = tags[i];
    if (t.name == "fmiModelDescription") {
      root = true;
      md.fmi_version = t.attrs.count("fmiVersion") ? t.attrs.at("fmiVersion") : "";
      md.model_name = t.attrs.count("modelName") ? t.attrs.at("modelName") : "";
      md.guid = t.attrs.count("guid") ? t.attrs.at("guid") : "";
    } else if (t.name == "CoSimulation") {
      md.co_simulation = true;
      md.model_identifier = t.attrs.count("modelIdentifier") ? t.attrs.at("modelIdentifier") : "";
    } else if (t.name == "DefaultExperiment" && t.attrs.count("stepSize")) {
      md.default_step = std::atof(t.attrs.at("stepSize").c_str());
    } else if (t.name == "SimpleType" && t.attrs.count("name") && i + 1 < tags.size() && tags[i + 1].name == "Real" &&
               tags[i + 1].attrs.count("unit")) {
      type_units[t.attrs.at("name")] = tags[i + 1].attrs.at("unit");
    } else if (t.name == "ScalarVariable") {
      FmuScalar v;
      v.name = t.attrs.count("name") ? t.attrs.at("name") : "";
      if (!t.attrs.count("valueReference")) throw std::runtime_error(source + ": ScalarVariable " + v.name + " has no valueReference");
      v.value_reference = static_cast<unsigned>(std::strtoul(t.attrs.at("valueReference").c_str(), nullptr, 10));
      v.causality = t.attrs.count("causality") ? t.attrs.at("causality") : "local";
      // The type is the first child element: Real, Integer, Boolean, String or Enumeration.
      if (i + 1 < tags.size() && tags[i + 1].name[0] != '/') v.type = tags[i + 1].name;
      // FMI 2.0 §2.2.7: a Real's unit is its own attribute, else its declaredType's (TypeDefinitions
      // come before ModelVariables).
      if (v.type == "Real") {
        const auto& a = tags[i + 1].attrs;
        if (a.count("unit"))
          v.unit = a.at("unit");
        else if (a.count("declaredType") && type_units.count(a.at("declaredType")))
          v.unit = type_units.at(a.at("declaredType"));
      }
      md.variables.push_back(v);
    }
  }
  if (!root) throw std::runtime_error(source + ": not an FMI model description (no <fmiModelDescription>)");
  if (md.fmi_version.rfind("2.", 0) != 0)
    throw std::runtime_error(source + ": fmiVersion '" + md.fmi_version + "' is not 2.0");
  if (!md.co_simulation) throw std::runtime_error(source + ": the FMU does not support co-simulation");
  if (md.model_identifier.empty()) throw std::runtime_error(source + ": CoSimulation has no modelIdentifier");
  // The library file is named after it, so it must be a plain name: the FMI
  // 2.0 standard (§2.2.1, fmiModelDescription) asks for a valid C identifier,
  // which also keeps "../" from loading a library outside the FMU.
  const std::string& id = md.model_identifier;
  bool identifier = std::isalpha(static_cast<unsigned char>(id[0])) || id[0] == '_';
  for (char ch : id) identifier = identifier && (std::isalnum(static_cast<unsigned char>(ch)) || ch == '_');
  if (!identifier || id.size() > 200)
    throw std::runtime_error(source + ": modelIdentifier '" + id +
                             "' is not a C identifier (letters, digits, _; not starting with a digit)");
  return md;
}

uint64_t fmu_unpack_limit() {
  const char* v = std::getenv("PCS_FMU_MAX_UNPACKED");
  if (v && *v) {
    char* end = nullptr;
    const unsigned long long n = std::strtoull(v, &end, 10);
    if (end && *end == '\0' && n > 0) return n;
  }
  return 1ull << 30;
}

namespace {
constexpr const char* kFolderPrefix = "tlm_host_fmu_";

// Removes tlm_host_fmu_<pid>_* folders of ours whose process no longer
// exists: what a host killed by SIGKILL (or a power loss) left behind. A
// folder whose pid is alive (or reused by a live process) is left alone.
void remove_folders_of_dead_hosts(const std::string& tmp_dir) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(tmp_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(kFolderPrefix, 0) != 0) continue;
    const std::string rest = name.substr(std::strlen(kFolderPrefix));
    const size_t underscore = rest.find('_');
    if (underscore == std::string::npos || underscore == 0 || underscore > 9) continue;
    if (rest.find_first_not_of("0123456789") != underscore) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(rest.substr(0, underscore)));
    struct stat st {};
    if (::lstat(entry.path().c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != ::geteuid()) continue;
    if (pid == ::getpid() || ::kill(pid, 0) == 0 || errno != ESRCH) continue;
    std::error_code rm;
    fs::remove_all(entry.path(), rm);
  }
}
}  // namespace

FmuArchive::FmuArchive(const std::string& fmu_path) : path_(fmu_path) {
  int err = 0;
  zip_t* z = zip_open(fmu_path.c_str(), ZIP_RDONLY, &err);
  if (!z) {
    zip_error_t ze;
    zip_error_init_with_code(&ze, err);
    std::string why = zip_error_strerror(&ze);
    zip_error_fini(&ze);
    throw FmuError("cannot open FMU '" + fmu_path + "': " + why);
  }
  const char* tmp = std::getenv("TMPDIR");
  const std::string tmp_dir = tmp && *tmp ? tmp : "/tmp";
  remove_folders_of_dead_hosts(tmp_dir);
  // The folder's name carries our process id, so a later host can tell it
  // was left by a host that was killed (kill -9 runs no clean-up).
  std::string templ = tmp_dir + "/" + kFolderPrefix + std::to_string(::getpid()) + "_XXXXXX";
  std::vector<char> buf(templ.begin(), templ.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data())) {
    zip_close(z);
    throw FmuError("cannot create a temporary folder for " + fmu_path);
  }
  dir_ = buf.data();
  try {
    // An FMU is a few MB; a zip bomb is not unpacked past the limit (the
    // bytes are counted as written, not trusted from the zip's directory).
    const uint64_t limit = fmu_unpack_limit();
    uint64_t written = 0;
    auto too_large = [&] {
      return FmuError(fmu_path + ": unpacks to more than " + std::to_string(limit) +
                      " bytes (PCS_FMU_MAX_UNPACKED raises the limit)");
    };
    zip_int64_t n = zip_get_num_entries(z, 0);
    if (n > 100000) throw FmuError(fmu_path + ": " + std::to_string(n) + " entries, more than any FMU has");
    for (zip_int64_t i = 0; i < n; ++i) {
      std::string name = zip_get_name(z, static_cast<zip_uint64_t>(i), 0);
      // Nothing may land outside our folder: no absolute paths, no "..".
      fs::path rel(name);
      if (rel.is_absolute() || name.find('\\') != std::string::npos)
        throw FmuError(fmu_path + ": entry '" + name + "' has an absolute path");
      for (const auto& part : rel)
        if (part == "..") throw FmuError(fmu_path + ": entry '" + name + "' leaves the FMU folder");
      fs::path out = fs::path(dir_) / rel;
      if (!name.empty() && name.back() == '/') {
        fs::create_directories(out);
        continue;
      }
      fs::create_directories(out.parent_path());
      zip_file_t* f = zip_fopen_index(z, static_cast<zip_uint64_t>(i), 0);
      if (!f) throw FmuError(fmu_path + ": cannot read entry " + name);
      std::ofstream o(out, std::ios::binary);
      char chunk[65536];
      zip_int64_t got;
      while ((got = zip_fread(f, chunk, sizeof chunk)) > 0) {
        written += static_cast<uint64_t>(got);
        if (written > limit) {
          zip_fclose(f);
          throw too_large();
        }
        o.write(chunk, got);
      }
      zip_fclose(f);
      if (got < 0 || !o) throw FmuError(fmu_path + ": cannot extract " + name);
    }
    zip_close(z);
    z = nullptr;
    if (!fs::exists(fs::path(dir_) / "modelDescription.xml")) throw FmuError(fmu_path + ": no modelDescription.xml");
    md_ = parse_model_description(config::read_text_file(dir_ + "/modelDescription.xml", "model description"),
                                  fmu_path + "/modelDescription.xml");
    std::string so = dir_ + "/binaries/linux64/" + md_.model_identifier + ".so";
    lib_ = dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!lib_) throw FmuError(fmu_path + ": cannot load binaries/linux64/" + md_.model_identifier + ".so: " + dlerror());
    // Our FMUs carry their own copy of socketlib, whose waits would not see
    // this process's stop signals: hand them the host's flag, so a signal
    // ends a wait inside the FMU (connect, handshake, RESULT, heartbeats)
    // within socketlib's 200 ms slice. Other FMUs lack the function.
    using SetStopFlagFn = void(const volatile sig_atomic_t*);
    if (auto* set_stop = reinterpret_cast<SetStopFlagFn*>(dlsym(lib_, "pcs_fmu_set_stop_flag")))
      set_stop(sl_get_stop_flag());
  } catch (...) {
    if (z) zip_close(z);
    std::error_code ec;
    fs::remove_all(dir_, ec);
    throw;
  }
}

FmuArchive::~FmuArchive() {
  if (lib_) dlclose(lib_);
  std::error_code ec;
  fs::remove_all(dir_, ec);  // leave nothing behind
}

FmuInstance::FmuInstance(std::shared_ptr<FmuArchive> archive, const std::string& instance_name, bool verbose)
    : archive_(std::move(archive)),
      callbacks_{pcs_fmu_logger, std::calloc, std::free, nullptr, &log_} {
  log_.instance = instance_name;
  log_.verbose = verbose;
  void* lib = archive_->library();
#define PCS_FMI2_LOAD(name)                                                                         \
  name = reinterpret_cast<name##TYPE*>(dlsym(lib, #name));                                          \
  if (!name) throw FmuError(archive_->path() + ": the FMU binary does not export " #name);
  PCS_FMI2_FUNCTIONS(PCS_FMI2_LOAD)
#undef PCS_FMI2_LOAD
  pcs_checkpoint_ = reinterpret_cast<CheckpointFn*>(dlsym(lib, "pcs_fmu_checkpoint"));
  pcs_resume_ = reinterpret_cast<ResumeFn*>(dlsym(lib, "pcs_fmu_resume"));
  pcs_confirm_resume_ = reinterpret_cast<ConfirmResumeFn*>(dlsym(lib, "pcs_fmu_confirm_resume"));
  pcs_stop_requested_ = reinterpret_cast<StopRequestedFn*>(dlsym(lib, "pcs_fmu_stop_requested"));
  const auto& md = archive_->description();
  c_ = fmi2Instantiate(instance_name.c_str(), fmi2CoSimulation, md.guid.c_str(), archive_->resource_uri().c_str(),
                       &callbacks_, fmi2False, verbose ? fmi2True : fmi2False);
  if (!c_)
    throw FmuError(archive_->path() + ": fmi2Instantiate failed" +
                   (log_.last_error.empty() ? std::string() : ": " + log_.last_error));
}

FmuInstance::~FmuInstance() {
  if (c_) fmi2FreeInstance(c_);
}

void FmuInstance::check(fmi2Status s, const char* call) {
  if (s == fmi2OK || s == fmi2Warning) return;
  std::string msg = log_.instance + ": " + call + " returned status " + std::to_string(static_cast<int>(s));
  if (!log_.last_error.empty()) msg += ": " + log_.last_error;
  throw FmuError(msg);
}

unsigned FmuInstance::vr(const std::string& variable) const {
  const FmuScalar* v = description().find(variable);
  if (!v) throw FmuError(archive_->path() + " has no variable '" + variable + "'");
  return v->value_reference;
}

void FmuInstance::set_real(unsigned vr, double v) { check(fmi2SetReal(c_, &vr, 1, &v), "fmi2SetReal"); }
void FmuInstance::set_reals(const std::vector<unsigned>& vr, const std::vector<double>& v) {
  if (!vr.empty()) check(fmi2SetReal(c_, vr.data(), vr.size(), v.data()), "fmi2SetReal");
}
double FmuInstance::get_real(unsigned vr) {
  double v = 0;
  check(fmi2GetReal(c_, &vr, 1, &v), "fmi2GetReal");
  return v;
}
void FmuInstance::set_integer(unsigned vr, int v) { check(fmi2SetInteger(c_, &vr, 1, &v), "fmi2SetInteger"); }
void FmuInstance::set_string(unsigned vr, const std::string& v) {
  fmi2String s = v.c_str();
  check(fmi2SetString(c_, &vr, 1, &s), "fmi2SetString");
}

std::string FmuInstance::get_string(unsigned vr) {
  fmi2String s = nullptr;
  check(fmi2GetString(c_, &vr, 1, &s), "fmi2GetString");
  return s ? s : "";
}
void FmuInstance::setup_experiment(double start, double stop) {
  check(fmi2SetupExperiment(c_, fmi2False, 0.0, start, fmi2True, stop), "fmi2SetupExperiment");
}
void FmuInstance::enter_initialization() { check(fmi2EnterInitializationMode(c_), "fmi2EnterInitializationMode"); }
void FmuInstance::exit_initialization() { check(fmi2ExitInitializationMode(c_), "fmi2ExitInitializationMode"); }
void FmuInstance::do_step(double t, double h) { check(fmi2DoStep(c_, t, h, fmi2True), "fmi2DoStep"); }
std::string FmuInstance::checkpoint() {
  if (!can_checkpoint()) throw FmuError(archive_->path() + ": this FMU cannot checkpoint (made by another tool or an older fmugen)");
  std::vector<char> path(4096);
  check(pcs_checkpoint_(c_, path.data(), path.size()), "pcs_fmu_checkpoint");
  return path.data();
}
void FmuInstance::resume(unsigned long long step) {
  if (!can_checkpoint()) throw FmuError(archive_->path() + ": this FMU cannot resume (made by another tool or an older fmugen)");
  check(pcs_resume_(c_, step), "pcs_fmu_resume");
}
void FmuInstance::confirm_resume() {
  if (pcs_confirm_resume_) check(pcs_confirm_resume_(c_), "pcs_fmu_confirm_resume");  // else: at the first step
}
bool FmuInstance::stop_requested() {
  if (!pcs_stop_requested_) return false;
  int requested = 0;
  check(pcs_stop_requested_(c_, &requested), "pcs_fmu_stop_requested");
  return requested != 0;
}
void FmuInstance::terminate() {
  if (terminated_) return;
  terminated_ = true;
  check(fmi2Terminate(c_), "fmi2Terminate");
}

}  // namespace tlm
