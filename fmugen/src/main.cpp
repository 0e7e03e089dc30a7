// fmugen: port configuration → FMI 2.0 co-simulation FMU.
//
//   fmugen ports.cfg -o scene.fmu [--binary pcs_fmu.so] [--description TEXT]
//
// The .fmu holds modelDescription.xml, binaries/linux64/<model>.so (the
// generic coupling FMU), resources/ports.cfg and documentation/.
#include <zip.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "config/cli.hpp"
#include "config/port_table.hpp"
#include "config/version.hpp"
#include "model_description.hpp"

namespace {

void add_entry(zip_t* z, const std::string& name, const std::string& data, const std::string& out) {
  // libzip copies the buffer only at zip_close; `data` must outlive it, so the
  // source is told to free a heap copy.
  void* copy = std::malloc(data.size() ? data.size() : 1);
  if (!copy) throw std::runtime_error("out of memory");
  std::memcpy(copy, data.data(), data.size());
  zip_source_t* src = zip_source_buffer(z, copy, data.size(), 1);
  if (!src || zip_file_add(z, name.c_str(), src, ZIP_FL_OVERWRITE | ZIP_FL_ENC_UTF_8) < 0) {
    if (src) zip_source_free(src);
    throw std::runtime_error("cannot add " + name + " to " + out + ": " + zip_strerror(z));
  }
}

int usage(std::ostream& os, int rc) {
  os << "usage: fmugen PORTS.cfg -o OUT.fmu [--binary FMU_LIBRARY.so] [--description TEXT]\n"
        "Generates an FMI 2.0 co-simulation FMU that couples to fe_server.\n"
        "  -h, --help, --version  this text; the version\n"
        "Exit codes: 0 written, 2 usage, 3 input rejected (the port configuration or the binary), 1 the FMU\n"
        "            could not be written.\n";
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  std::string ports, out, description = "Co-simulation of a hydraulic percussion unit with fe_server";
  std::string binary = PCS_FMU_BINARY;  // the pcs_fmu module of this build
  try {
    config::Args args(argc, argv);
    while (args.next()) {
      if (args.is("-o") || args.is("--output")) out = args.value();
      else if (args.is("--binary")) binary = args.value();
      else if (args.is("--description")) description = args.value();
      else if (args.is("-h") || args.is("--help")) return usage(std::cout, 0);
      else if (args.is("--version")) return std::cout << config::version_line("fmugen") << "\n", 0;
      else if (args.is_option()) args.unknown();
      else if (ports.empty()) ports = args.current();
      else throw std::invalid_argument("unexpected argument '" + args.current() + "'");
    }
    if (ports.empty()) throw std::invalid_argument("no port configuration given");
    if (out.empty()) throw std::invalid_argument("no output given (-o OUT.fmu)");
  } catch (const std::exception& e) {
    std::cerr << "fmugen: " << e.what() << "\n(fmugen --help lists the options)\n";
    return 2;
  }
  config::PortTable table;
  std::string so;
  try {  // what it reads: a fault there is the input's (exit 3, as the other tools)
    table = config::read_port_table(ports);
    so = config::read_text_file(binary, "FMU binary");
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
      add_entry(z, "modelDescription.xml", fmugen::model_description_xml(table, description), out);
      add_entry(z, "binaries/linux64/" + table.model_name + ".so", so, out);
      add_entry(z, "resources/ports.cfg", config::read_text_file(ports, "port configuration"), out);
      add_entry(z, "documentation/externalDependencies.txt",
                fmugen::external_dependencies_text(table), out);
    } catch (...) {
      zip_discard(z);
      throw;
    }
    if (zip_close(z) < 0) throw std::runtime_error("cannot write " + out + ": " + zip_strerror(z));
    std::cout << "fmugen: wrote " << out << " (model " << table.model_name << ", "
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
