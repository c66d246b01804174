#include "dict_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "flipper/sdk/errors.hpp"

namespace flipper::plugins::wordnet {
namespace {
constexpr std::size_t kChunk = 512;  // index lines are ~60 bytes, synset lines mostly < 512
}  // namespace

DictFile::DictFile(const std::string& path, std::size_t max_probes)
    : path_(path), max_probes_(max_probes) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw sdk::Error(sdk::codes::kBadConfig, "wordnet: cannot open '" + path + "'");
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    ::close(fd_);
    throw sdk::Error(sdk::codes::kBadConfig, "wordnet: cannot stat '" + path + "'");
  }
  size_ = static_cast<std::size_t>(st.st_size);
}

DictFile::~DictFile() {
  ::close(fd_);
}

std::size_t DictFile::read(std::size_t at, char* buf, std::size_t n) const {
  if (at >= size_) return 0;
  n = std::min(n, size_ - at);
  reads_.fetch_add(1, std::memory_order_relaxed);
  std::size_t done = 0;
  while (done < n) {
    const ssize_t r = ::pread(fd_, buf + done, n - done, static_cast<off_t>(at + done));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) throw sdk::Error(sdk::codes::kInternal, "wordnet: cannot read '" + path_ + "'");
    done += static_cast<std::size_t>(r);
  }
  return done;
}

std::string DictFile::line_from(std::size_t start) const {
  std::string out;
  char buf[kChunk];
  for (std::size_t at = start; at < size_;) {
    const std::size_t n = read(at, buf, kChunk);
    const char* nl = std::find(buf, buf + n, '\n');
    out.append(buf, static_cast<std::size_t>(nl - buf));
    if (nl != buf + n) break;
    at += n;
  }
  return out;
}

std::size_t DictFile::line_start(std::size_t pos, std::size_t lo) const {
  char buf[kChunk];
  while (pos > lo) {
    const std::size_t from = pos - std::min(kChunk, pos - lo);
    const std::size_t n = read(from, buf, pos - from);
    for (std::size_t i = n; i > 0; --i)
      if (buf[i - 1] == '\n') return from + i;
    pos = from;
  }
  return lo;
}

std::string DictFile::range(std::size_t lo, std::size_t hi) const {
  if (lo >= std::min(hi, size_)) return {};
  std::string out(std::min(hi, size_) - lo, '\0');
  out.resize(read(lo, out.data(), out.size()));
  return out;
}

DictFile::Probe DictFile::probe(std::size_t lo, std::size_t hi) const {
  const bool cacheable = hi <= UINT32_MAX;
  const std::uint64_t key = (static_cast<std::uint64_t>(lo) << 32) | hi;
  if (cacheable) {
    std::lock_guard<std::mutex> lock(probes_mutex_);
    if (auto it = probes_.find(key); it != probes_.end()) return it->second;
  }
  Probe p;
  p.start = line_start(lo + (hi - lo) / 2, lo);
  const std::string line = line_from(p.start);
  p.length = line.size();
  p.key = line.substr(0, line.find(' '));
  if (cacheable) {
    std::lock_guard<std::mutex> lock(probes_mutex_);
    if (probes_.size() < max_probes_) probes_.emplace(key, p);
  }
  return p;
}

}  // namespace flipper::plugins::wordnet
