// Fuzz target: the FMU importer's unpacking. The input is the .fmu (a zip
// archive); FmuArchive unpacks it into its temporary folder (refusing
// entries that leave it, a modelIdentifier that is not a C identifier, more
// than the unpack limit), reads modelDescription.xml and tries to load the
// library. Whatever it refuses, its folder must be gone afterwards.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_folder.hpp"

#include "fmu_importer.hpp"

namespace {
const std::string& folder() {
  static const std::string& dir = [] () -> const std::string& {
    const std::string& d = fuzz_support::private_folder("pcs_fuzz_fmu");
    setenv("TMPDIR", d.c_str(), 1);                 // the importer unpacks here
    setenv("PCS_FMU_MAX_UNPACKED", "1000000", 1);  // 1 MB: a bomb is stopped quickly
    return d;
  }();
  return dir;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = folder() + "/input.fmu";
  {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    tlm::FmuArchive archive(path);
  } catch (const std::exception&) {
  }
  // Nothing but the input may remain: every unpacked folder is removed.
  for (const auto& e : std::filesystem::directory_iterator(folder()))
    if (e.path().filename() != "input.fmu") {
      std::fprintf(stderr, "fuzz_fmu_unpack: %s left behind\n", e.path().c_str());
      std::abort();
    }
  return 0;
}
