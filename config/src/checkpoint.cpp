#include "config/checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>

#include "config/keyword_reader.hpp"
#include "socketlib/auth.h"

namespace config {

namespace {
constexpr char kMagic[8] = {'P', 'C', 'S', '-', 'C', 'K', 'P', 'T'};
constexpr uint32_t kFormat = 1;

void put_u64(std::vector<uint8_t>& b, uint64_t v) {
  for (int i = 0; i < 8; ++i) b.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
uint64_t get_u64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<uint64_t>(p[i]) << (8 * i);
  return v;
}
}  // namespace

namespace {
std::string sha256_hex(const uint8_t* data, size_t size) {
  uint8_t sum[PCS_SHA256_SIZE];
  pcs_sha256(data, size, sum);
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (uint8_t b : sum) out += hex[b >> 4], out += hex[b & 15];
  return out;
}
}  // namespace

std::string file_sha256(const std::string& path) {
  std::vector<uint8_t> bytes;
  try {
    bytes = read_binary_file(path, "file to digest");
  } catch (const std::runtime_error& e) {
    throw CheckpointError(e.what());
  }
  return sha256_hex(bytes.data(), bytes.size());
}

std::string text_sha256(const std::string& text) {
  return sha256_hex(reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

void StateIO::mismatch(const char* name, uint64_t in_file, size_t in_run) {
  throw CheckpointError("record '" + std::string(name) + "': " + std::to_string(in_file) + " elements, this run has " +
                        std::to_string(in_run) + " (another model?)");
}

void StateIO::text(const char* name, std::string& s) {
  std::vector<char> v(s.begin(), s.end());
  list(name, v);  // a text may differ in length: expect() says how
  if (!saving()) s.assign(v.begin(), v.end());
}

void StateIO::expect(const char* name, uint64_t expected, const std::string& what) {
  uint64_t v = expected;
  value(name, v);
  if (v != expected)
    throw CheckpointError(what + ": the checkpoint has " + std::to_string(v) + ", this run has " + std::to_string(expected));
}

void StateIO::expect(const char* name, const std::string& expected, const std::string& what) {
  std::string v = expected;
  text(name, v);
  if (v != expected) throw CheckpointError(what + ": the checkpoint has '" + v + "', this run has '" + expected + "'");
}

StateWriter::StateWriter() {
  buf_.insert(buf_.end(), kMagic, kMagic + 8);
  put_u64(buf_, kFormat);
}

void StateWriter::raw(const char* name, void* data, size_t elem_size, uint64_t count) {
  const size_t len = std::strlen(name);
  put_u64(buf_, len);
  buf_.insert(buf_.end(), name, name + len);
  put_u64(buf_, elem_size);
  put_u64(buf_, count);
  const auto* p = static_cast<const uint8_t*>(data);
  if (count) buf_.insert(buf_.end(), p, p + elem_size * count);
}

void StateWriter::write(const std::string& path) const {
  uint8_t sum[PCS_SHA256_SIZE];
  pcs_sha256(buf_.data(), buf_.size(), sum);
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw CheckpointError("cannot write checkpoint '" + tmp + "': " + std::strerror(errno));
  auto put = [&](const uint8_t* p, size_t n) {
    while (n > 0) {
      const ssize_t w = ::write(fd, p, n);
      if (w < 0 && errno == EINTR) continue;  // a signal (the one that asked for this checkpoint, maybe)
      if (w <= 0) {
        const std::string why = std::strerror(errno);
        ::close(fd);
        ::unlink(tmp.c_str());
        throw CheckpointError("cannot write checkpoint '" + tmp + "': " + why);
      }
      p += w;
      n -= static_cast<size_t>(w);
    }
  };
  put(buf_.data(), buf_.size());
  put(sum, sizeof sum);
  // On disk before the rename, so the name never points at a partial file.
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw CheckpointError("cannot write checkpoint '" + tmp + "': " + why);
  }
  // The previous checkpoint stays as FILE.prev: the other side of a
  // co-simulation writes its own just after this one, and a node lost in
  // between leaves this side a step ahead; the pair of that step is then
  // FILE.prev and the other side's file.
  std::rename(path.c_str(), (path + ".prev").c_str());  // none before the first
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw CheckpointError("cannot rename checkpoint '" + tmp + "' to '" + path + "': " + std::strerror(errno));
}

StateReader::StateReader(const std::string& path) : path_(path) {
  try {
    buf_ = read_binary_file(path, "checkpoint");  // a regular file, at most kMaxInputFileBytes
  } catch (const std::runtime_error& e) {
    throw CheckpointError(e.what());
  }
  if (buf_.size() < 16 + PCS_SHA256_SIZE || std::memcmp(buf_.data(), kMagic, 8) != 0)
    throw CheckpointError("'" + path + "' is not a checkpoint file");
  if (get_u64(buf_.data() + 8) != kFormat)
    throw CheckpointError("checkpoint '" + path + "' has format " + std::to_string(get_u64(buf_.data() + 8)) +
                          ", this program reads format " + std::to_string(kFormat));
  end_ = buf_.size() - PCS_SHA256_SIZE;
  uint8_t sum[PCS_SHA256_SIZE];
  pcs_sha256(buf_.data(), end_, sum);
  if (std::memcmp(sum, buf_.data() + end_, PCS_SHA256_SIZE) != 0)
    throw CheckpointError("checkpoint '" + path + "' is damaged (its checksum does not match its contents)");
  pos_ = 16;
}

StateReader::Header StateReader::peek(const char* want) const {
  auto fail = [&](const std::string& why) {
    throw CheckpointError("checkpoint '" + path_ + "', record " + std::to_string(record_ + 1) + " ('" + want +
                          "' expected): " + why);
  };
  Header h;
  size_t p = pos_;
  if (p + 8 > end_) fail("the file ends here");
  const uint64_t len = get_u64(buf_.data() + p);
  p += 8;
  if (len > end_ - p) fail("a damaged record");
  h.name.assign(reinterpret_cast<const char*>(buf_.data() + p), static_cast<size_t>(len));
  p += static_cast<size_t>(len);
  if (p + 16 > end_) fail("a damaged record");
  h.elem_size = get_u64(buf_.data() + p);
  h.count = get_u64(buf_.data() + p + 8);
  p += 16;
  if (h.elem_size != 0 && h.count > (end_ - p) / h.elem_size) fail("a damaged record");
  h.data = p;
  if (h.name != want) fail("found '" + h.name + "' (written by another model or program version)");
  return h;
}

uint64_t StateReader::next_count(const char* name, size_t elem_size) {
  const Header h = peek(name);
  if (h.elem_size != elem_size)
    throw CheckpointError("checkpoint '" + path_ + "', record '" + name + "': elements of " +
                          std::to_string(h.elem_size) + " bytes, expected " + std::to_string(elem_size));
  return h.count;
}

void StateReader::raw(const char* name, void* data, size_t elem_size, uint64_t count) {
  const Header h = peek(name);
  if (h.elem_size != elem_size || h.count != count)
    throw CheckpointError("checkpoint '" + path_ + "', record '" + name + "': " + std::to_string(h.count) + " × " +
                          std::to_string(h.elem_size) + " bytes, this run has " + std::to_string(count) + " × " +
                          std::to_string(elem_size) + " (another model?)");
  if (count) std::memcpy(data, buf_.data() + h.data, static_cast<size_t>(elem_size * count));
  pos_ = h.data + static_cast<size_t>(elem_size * count);
  ++record_;
}

void StateReader::finish() const {
  if (pos_ != end_)
    throw CheckpointError("checkpoint '" + path_ + "' holds more state than this run has (after record " +
                          std::to_string(record_) + "): another model or program version");
}

}  // namespace config
