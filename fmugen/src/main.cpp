// fmugen: port configuration → FMI 2.0 or 3.0 co-simulation FMU.
//
//   fmugen ports.cfg -o scene.fmu [--fmi 2|3] [--binary pcs_fmu.so] [--description TEXT]
//
// The .fmu holds modelDescription.xml, binaries/linux64/<model>.so (the
// generic coupling FMU), resources/ports.cfg and documentation/ (index.html,
// externalDependencies.txt, licenses/).
#include <zip.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "config/cli.hpp"
#include "config/port_table.hpp"
#include "config/version.hpp"
#include "model_description.hpp"

namespace {

// Entries are 0644 (a world-writable .so after unzip otherwise) and carry
// the generation time, so SOURCE_DATE_EPOCH gives a byte-identical FMU.
void add_entry(zip_t* z, const std::string& name, const std::string& data, const std::string& out,
               std::time_t mtime) {
  // libzip copies the buffer only at zip_close; `data` must outlive it, so the
  // source is told to free a heap copy.
  void* copy = std::malloc(data.size() ? data.size() : 1);
  if (!copy) throw std::runtime_error("out of memory");
  std::memcpy(copy, data.data(), data.size());
  zip_source_t* src = zip_source_buffer(z, copy, data.size(), 1);
  zip_int64_t index = -1;
  if (!src || (index = zip_file_add(z, name.c_str(), src, ZIP_FL_OVERWRITE | ZIP_FL_ENC_UTF_8)) < 0) {
    if (src) zip_source_free(src);
    throw std::runtime_error("cannot add " + name + " to " + out + ": " + zip_strerror(z));
  }
  const auto i = static_cast<zip_uint64_t>(index);
  if (zip_file_set_external_attributes(z, i, 0, ZIP_OPSYS_UNIX, (0100644u) << 16) < 0 ||
      zip_file_set_mtime(z, i, mtime, 0) < 0)
    throw std::runtime_error("cannot set the mode of " + name + " in " + out + ": " + zip_strerror(z));
}

// The generation time: SOURCE_DATE_EPOCH (reproducible builds) if set, else now.
std::time_t generation_time() {
  if (const char* e = std::getenv("SOURCE_DATE_EPOCH")) {
    char* end = nullptr;
    const long long v = std::strtoll(e, &end, 10);
    if (end == e || *end != '\0' || v < 0)
      throw std::invalid_argument(std::string("SOURCE_DATE_EPOCH '") + e + "' is not a number of seconds");
    return static_cast<std::time_t>(v);
  }
  return std::time(nullptr);
}

std::string iso8601_utc(std::time_t t) {
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// The licences of what the binary links in statically, found at configure
// time (CMake's PCS_FMU_LICENSES: "entry=path|..."): documentation/licenses/.
std::vector<std::pair<std::string, std::string>> licence_files() {
  std::vector<std::pair<std::string, std::string>> out;
  const std::string all = PCS_FMU_LICENSES;
  std::stringstream list(all);
  std::string item;
  while (std::getline(list, item, '|')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == item.size()) continue;
    out.emplace_back(item.substr(0, eq), item.substr(eq + 1));
  }
  return out;
}

int usage(std::ostream& os, int rc) {
  os << "usage: fmugen PORTS.cfg -o OUT.fmu [--fmi 2|3] [--binary FMU_LIBRARY.so] [--binary-win64 FMU.dll | --no-win64]\n"
        "              [--description TEXT]\n"
        "Generates an FMI 2.0 (or, with --fmi 3, FMI 3.0) co-simulation FMU that couples to fe_server.\n"
        "  --description TEXT     the FMU's description (default: the port table's, else one from its ports)\n"
        "  --binary FILE          another FMU library (then no win64 DLL, unless --binary-win64 names its twin)\n"
        "  -h, --help, --version  this text; the version\n"
        "Exit codes: 0 written, 2 usage, 3 input rejected (the port configuration or the binary), 1 the FMU\n"
        "            could not be written.\n";
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  std::string ports, out, description;  // empty: the table's, else one from its ports
  std::string binary = PCS_FMU_BINARY;  // the pcs_fmu module of this build (FMI 2.0 and 3.0)
  std::string binary_win64 = PCS_FMU_BINARY_WIN64;  // its win64 DLL, if this build made one
  bool binary_given = false, win64_given = false;
  int fmi = 2;
  try {
    config::Args args(argc, argv);
    while (args.next()) {
      if (args.is("-o") || args.is("--output")) out = args.value();
      else if (args.is("--binary")) binary = args.value(), binary_given = true;
      else if (args.is("--binary-win64")) binary_win64 = args.value(), win64_given = true;
      else if (args.is("--no-win64")) binary_win64.clear();
      else if (args.is("--description")) description = args.value();
      else if (args.is("--fmi")) {
        const std::string v = args.value();
        if (v != "2" && v != "3") throw std::invalid_argument("--fmi " + v + ": expected 2 (FMI 2.0, the default) or 3 (FMI 3.0)");
        fmi = v[0] - '0';
      }
      else if (args.is("-h") || args.is("--help")) return usage(std::cout, 0);
      else if (args.is("--version")) return std::cout << config::version_line("fmugen") << "\n", 0;
      else if (args.is_option()) args.unknown();
      else if (ports.empty()) ports = args.current();
      else throw std::invalid_argument("unexpected argument '" + args.current() + "'");
    }
    // Another binary with this build's DLL would pair two different builds in one FMU.
    if (binary_given && !win64_given) binary_win64.clear();
    if (ports.empty()) throw std::invalid_argument("no port configuration given");
    if (out.empty()) throw std::invalid_argument("no output given (-o OUT.fmu)");
  } catch (const std::exception& e) {
    std::cerr << "fmugen: " << e.what() << "\n(fmugen --help lists the options)\n";
    return 2;
  }
  config::PortTable table;
  std::string so, dll;
  std::time_t when = 0;
  std::vector<std::pair<std::string, std::string>> licences;
  try {  // what it reads: a fault there is the input's (exit 3, as the other tools)
    table = config::read_port_table(ports);
    so = config::read_text_file(binary, "FMU binary");
    if (!binary_win64.empty()) dll = config::read_text_file(binary_win64, "FMU win64 binary");
    when = generation_time();
    for (const auto& [entry, path] : licence_files())
      licences.emplace_back(entry, config::read_text_file(path, "licence text"));
  } catch (const std::exception& e) {
    std::cerr << "fmugen: " << e.what() << "\n";
    return 3;
  }
  try {
    std::remove(out.c_str());
    int err = 0;
    zip_t* z = zip_open(out.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
    if (!z) {
      zip_error_t ze;
      zip_error_init_with_code(&ze, err);
      std::string why = zip_error_strerror(&ze);
      zip_error_fini(&ze);
      throw std::runtime_error("cannot create " + out + ": " + why);
    }
    try {
      const fmugen::Generation gen{config::version_line("fmugen"), iso8601_utc(when)};
      // FMI 3.0 names the platform folder by architecture and OS (2.10.1).
      add_entry(z, "modelDescription.xml",
                fmi == 3 ? fmugen::model_description_xml3(table, description, gen)
                         : fmugen::model_description_xml(table, description, gen),
                out, when);
      add_entry(z, std::string(fmi == 3 ? "binaries/x86_64-linux/" : "binaries/linux64/") + table.model_name + ".so", so,
                out, when);
      if (!dll.empty())
        add_entry(z, std::string(fmi == 3 ? "binaries/x86_64-windows/" : "binaries/win64/") + table.model_name + ".dll",
                  dll, out, when);
      add_entry(z, "resources/ports.cfg", config::read_text_file(ports, "port configuration"), out, when);
      add_entry(z, "documentation/index.html", fmugen::documentation_html(table, description, gen), out, when);
      add_entry(z, "documentation/externalDependencies.txt",
                fmugen::external_dependencies_text(table), out, when);
      for (const auto& [entry, text] : licences) add_entry(z, "documentation/licenses/" + entry, text, out, when);
    } catch (...) {
      zip_discard(z);
      throw;
    }
    if (zip_close(z) < 0) throw std::runtime_error("cannot write " + out + ": " + zip_strerror(z));
    std::cout << "fmugen: wrote " << out << " (FMI " << (fmi == 3 ? "3.0" : "2.0") << (dll.empty() ? ", linux64" : ", linux64 and win64") << ", model " << table.model_name << ", "
              << table.to_fe.size() << " inputs, " << table.to_host.size() << " outputs, guid "
              << config::fmu_guid(table) << ")\n";
    if (table.hopsan)  // what a Hopsan user pastes into FMIWrapperQ (also in documentation/externalDependencies.txt)
      std::cout << "fmugen: Hopsan FMIWrapperQ portspecs: " << config::hopsan_portspecs(table) << "\n";
  } catch (const std::exception& e) {
    std::cerr << "fmugen: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
