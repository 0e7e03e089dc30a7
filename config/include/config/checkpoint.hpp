// Checkpoint files: the complete state of one side of a co-simulation
// (fe_server's solver, tlm_host's components), written at a step boundary
// so that a run resumed from it continues bit for bit as if never stopped.
//
// One function per stateful object, `void state(config::StateIO& io)`,
// lists its mutable members with io.value / io.array; the same function
// saves (StateWriter) and restores (StateReader), so the two cannot
// disagree on order. Every record carries its name, element size and count;
// the reader checks all three, so a checkpoint of another model or version
// is refused with the record that differs rather than read as garbage.
//
// File: "PCS-CKPT", format version (u32), the records, then the SHA-256 of
// everything before it (libsodium). Written to FILE.tmp, flushed to disk
// and renamed: a crash while writing leaves the previous checkpoint intact;
// the one it replaces stays as FILE.prev.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace config {

class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Hex SHA-256 of a file's bytes (a deck's or model's identity in a
// checkpoint); throws CheckpointError if unreadable.
std::string file_sha256(const std::string& path);
// The same of a text (what a run was given beside its files).
std::string text_sha256(const std::string& text);

class StateIO {
 public:
  virtual ~StateIO() = default;
  virtual bool saving() const = 0;

  // One value: an arithmetic type, or a fixed-size aggregate of them
  // (Eigen's fixed-size vectors and matrices).
  template <class T>
  void value(const char* name, T& v) {
    check_plain<T>();
    raw(name, &v, sizeof(T), 1);
  }
  // A vector of such values whose length the run has fixed (to its nodes,
  // elements, delay...): restoring, the file must hold that length, else
  // CheckpointError; a file of another model, or a forged one, never changes
  // the length of an array the code indexes by the model.
  template <class T>
  void array(const char* name, std::vector<T>& v) {
    exchange(name, v, true);
  }
  // A list whose length is state itself (contact candidates, snapshot
  // times, impacts): restored to the file's length.
  template <class T>
  void list(const char* name, std::vector<T>& v) {
    exchange(name, v, false);
  }
  void array(const char* name, std::vector<bool>&) = delete;  // not contiguous
  void text(const char* name, std::string& s);
  // A value the reader must find equal to `expected` (a model's size, a
  // port table's hash): else CheckpointError "<what>: the checkpoint has A,
  // this run has B".
  void expect(const char* name, uint64_t expected, const std::string& what);
  void expect(const char* name, const std::string& expected, const std::string& what);

 protected:
  template <class T>
  void exchange(const char* name, std::vector<T>& v, bool fixed) {
    check_plain<T>();
    uint64_t n = v.size();
    if (!saving()) {
      n = next_count(name, sizeof(T));
      if (fixed && n != v.size()) mismatch(name, n, v.size());
      v.resize(static_cast<size_t>(n));
    }
    raw(name, v.data(), sizeof(T), n);
  }
  // Save or restore count elements of elem_size bytes at data.
  virtual void raw(const char* name, void* data, size_t elem_size, uint64_t count) = 0;
  // Reader: the count of the next record, checked to be `name` with elements of elem_size.
  virtual uint64_t next_count(const char* name, size_t elem_size) = 0;
  [[noreturn]] static void mismatch(const char* name, uint64_t in_file, size_t in_run);

 private:
  template <class T>
  static constexpr void check_plain() {
    static_assert(std::is_standard_layout_v<T> && !std::is_pointer_v<T>,
                  "StateIO stores plain values (numbers, fixed-size Eigen types), not pointers or classes");
  }
};

class StateWriter final : public StateIO {
 public:
  StateWriter();
  bool saving() const override { return true; }
  // Write the records (plus checksum) to `path` atomically.
  void write(const std::string& path) const;
  const std::vector<uint8_t>& bytes() const { return buf_; }

 protected:
  void raw(const char* name, void* data, size_t elem_size, uint64_t count) override;
  uint64_t next_count(const char*, size_t) override { return 0; }

 private:
  std::vector<uint8_t> buf_;
};

class StateReader final : public StateIO {
 public:
  // Reads and verifies the file (magic, version, checksum). Throws
  // CheckpointError naming the file.
  explicit StateReader(const std::string& path);
  bool saving() const override { return false; }
  // Every record consumed? (CheckpointError otherwise: the checkpoint holds
  // state this run does not have.)
  void finish() const;
  const std::string& path() const { return path_; }

 protected:
  void raw(const char* name, void* data, size_t elem_size, uint64_t count) override;
  uint64_t next_count(const char* name, size_t elem_size) override;

 private:
  struct Header {
    std::string name;
    uint64_t elem_size = 0, count = 0;
    size_t data = 0;  // offset of the record's bytes
  };
  Header peek(const char* want) const;
  std::string path_;
  std::vector<uint8_t> buf_;
  size_t pos_ = 0, end_ = 0;
  size_t record_ = 0;
};

}  // namespace config
