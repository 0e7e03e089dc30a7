// Child processes for two-process tests: start, wait with a hard time-out
// (the child is killed when it runs past it), and read the port file a
// server writes after binding an ephemeral loopback port.
#pragma once

#include <string>
#include <vector>

namespace testing_support {

class ChildProcess {
 public:
  // Starts argv[0] with stdout and stderr captured to a temporary file.
  explicit ChildProcess(const std::vector<std::string>& argv);
  ~ChildProcess();  // kills the child if it still runs
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // Exit code, or -1000 - signal if killed by a signal; -1 if it did not end
  // within timeout_s (it is then killed).
  int wait(double timeout_s);
  std::string output() const;  // what it printed so far
  int pid() const { return pid_; }

 private:
  int pid_ = -1;
  bool done_ = false;
  int status_ = 0;
  std::string log_path_;
};

// Sets (value) or unsets (nullptr) an environment variable for its scope:
// children started meanwhile inherit it; the old value comes back after.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value);
  ~ScopedEnv();
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string name_, old_;
  bool had_ = false;
};

// Wait until `path` holds a port number (the server is listening); -1 on time-out.
int read_port_file(const std::string& path, double timeout_s);

// A fresh temporary directory, removed by the destructor.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }
  // A file only the owner may read (mode 600) holding `content`: a token file.
  std::string private_file(const std::string& name, const std::string& content) const;

 private:
  std::string path_;
};

}  // namespace testing_support
