// tlm_host's FMI 2.0 co-simulation importer: unzip the .fmu into a private
// temporary folder (removed again when the archive is released), read
// modelDescription.xml, dlopen binaries/linux64/<modelIdentifier>.so and call
// it through the 34 standard functions.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "fmi2/fmi2.h"

namespace tlm {

struct FmuScalar {
  std::string name;
  unsigned value_reference = 0;
  std::string causality;  // input, output, parameter, ...
  std::string type;       // Real, Integer, Boolean, String
  std::string unit;       // a Real's unit, its own or its declaredType's; empty if none
};

struct ModelDescription {
  std::string fmi_version, model_name, guid, model_identifier;
  bool co_simulation = false;
  double default_step = 0.0;
  std::vector<FmuScalar> variables;
  const FmuScalar* find(const std::string& name) const;
};

// Reads the subset of modelDescription.xml an importer needs. Throws
// std::runtime_error naming `source` for a malformed or non-2.0 file.
ModelDescription parse_model_description(const std::string& xml, const std::string& source);

// Largest number of bytes an FMU may unpack to: 1 GiB, or the environment
// variable PCS_FMU_MAX_UNPACKED (bytes).
uint64_t fmu_unpack_limit();

class FmuArchive {
 public:
  explicit FmuArchive(const std::string& fmu_path);
  ~FmuArchive();
  FmuArchive(const FmuArchive&) = delete;
  FmuArchive& operator=(const FmuArchive&) = delete;
  const std::string& path() const { return path_; }
  const std::string& dir() const { return dir_; }
  const ModelDescription& description() const { return md_; }
  std::string resource_uri() const { return "file://" + dir_ + "/resources"; }
  void* library() const { return lib_; }

 private:
  std::string path_, dir_;
  ModelDescription md_;
  void* lib_ = nullptr;
};

class FmuError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class FmuInstance {
 public:
  FmuInstance(std::shared_ptr<FmuArchive> archive, const std::string& instance_name, bool verbose);
  ~FmuInstance();
  FmuInstance(const FmuInstance&) = delete;
  FmuInstance& operator=(const FmuInstance&) = delete;

  const ModelDescription& description() const { return archive_->description(); }
  unsigned vr(const std::string& variable) const;  // throws if absent
  void set_real(unsigned vr, double v);
  void set_reals(const std::vector<unsigned>& vr, const std::vector<double>& v);
  double get_real(unsigned vr);
  void set_integer(unsigned vr, int v);
  void set_string(unsigned vr, const std::string& v);
  std::string get_string(unsigned vr);
  void setup_experiment(double start, double stop);
  void enter_initialization();
  void exit_initialization();
  void do_step(double t, double h);
  void terminate();
  // Our FMUs' checkpoint functions (fmu/src/fmi2_functions.cpp), beyond
  // FMI: FmuError for an FMU without them ("cannot checkpoint").
  bool can_checkpoint() const { return pcs_checkpoint_ && pcs_resume_; }
  std::string checkpoint();            // the server's checkpoint file
  void resume(unsigned long long step);  // before exit_initialization()
  void confirm_resume();                 // after it: the server's answer (throws if it refused)
  // fe_server got a stop signal and asks for a checkpoint (false for FMUs
  // without the function).
  bool stop_requested();

  // The log sink the FMU's logger callback writes to.
  struct Log {
    std::string instance;
    std::string last_error;
    bool verbose = false;
  };

 private:
  void check(fmi2Status s, const char* call);
  std::shared_ptr<FmuArchive> archive_;
  Log log_;
  fmi2CallbackFunctions callbacks_;
  fmi2Component c_ = nullptr;
  bool terminated_ = false;
  using CheckpointFn = fmi2Status(fmi2Component, char*, size_t);
  using ResumeFn = fmi2Status(fmi2Component, unsigned long long);
  CheckpointFn* pcs_checkpoint_ = nullptr;
  ResumeFn* pcs_resume_ = nullptr;
  using ConfirmResumeFn = fmi2Status(fmi2Component);
  ConfirmResumeFn* pcs_confirm_resume_ = nullptr;
  using StopRequestedFn = fmi2Status(fmi2Component, int*);
  StopRequestedFn* pcs_stop_requested_ = nullptr;
#define PCS_FMI2_MEMBER(name) name##TYPE* name = nullptr;
  PCS_FMI2_FUNCTIONS(PCS_FMI2_MEMBER)
#undef PCS_FMI2_MEMBER
};

}  // namespace tlm
