// Reading files that cannot be FIFOs, devices or huge.
#include "flipper/toolkit/config/regular_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "flipper/sdk/errors.hpp"

namespace flipper::toolkit::config {
namespace {
// Owns a descriptor opened without blocking (opening a FIFO with no writer would hang).
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

void open_checked(Fd& f, const std::string& path, std::uint64_t max_bytes, const std::string& what,
                  const char* missing_code, struct stat& st) {
  f.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (f.fd < 0)
    throw sdk::Error(missing_code,
                     "cannot read " + what + " '" + path + "': " + std::strerror(errno));
  if (::fstat(f.fd, &st) != 0)
    throw sdk::Error(missing_code,
                     "cannot read " + what + " '" + path + "': " + std::strerror(errno));
  if (!S_ISREG(st.st_mode))
    throw sdk::Error(sdk::codes::kNotARegularFile,
                     what + " '" + path + "' is not a regular file (only regular files are read)");
  if (static_cast<std::uint64_t>(st.st_size) > max_bytes)
    throw sdk::Error(
        sdk::codes::kFileTooLarge,
        what + " '" + path + "' has " + std::to_string(st.st_size) +
            " bytes; the limit is input.max_file_bytes = " + std::to_string(max_bytes));
}

}  // namespace

std::string read_regular_file(const std::string& path, std::uint64_t max_bytes,
                              const std::string& what, const char* missing_code) {
  Fd f;
  struct stat st {};
  open_checked(f, path, max_bytes, what, missing_code, st);
  std::string out;
  out.resize(static_cast<std::size_t>(st.st_size));
  std::size_t got = 0;
  char chunk[65536];
  for (;;) {
    const ssize_t n = ::read(f.fd, chunk, sizeof chunk);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw sdk::Error(missing_code,
                       "cannot read " + what + " '" + path + "': " + std::strerror(errno));
    }
    if (n == 0) break;
    if (got + static_cast<std::size_t>(n) > max_bytes)
      throw sdk::Error(
          sdk::codes::kFileTooLarge,
          what + " '" + path + "' grew beyond input.max_file_bytes = " + std::to_string(max_bytes));
    if (got + static_cast<std::size_t>(n) > out.size())
      out.resize(got + static_cast<std::size_t>(n));
    std::memcpy(out.data() + got, chunk, static_cast<std::size_t>(n));
    got += static_cast<std::size_t>(n);
  }
  out.resize(got);
  return out;
}

void check_regular_file(const std::string& path, std::uint64_t max_bytes, const std::string& what,
                        const char* missing_code) {
  Fd f;
  struct stat st {};
  open_checked(f, path, max_bytes, what, missing_code, st);
}

}  // namespace flipper::toolkit::config
