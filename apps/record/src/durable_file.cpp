// Atomic whole-file writes and checked appends (durable_file.hpp, docs/experiments.md
// "Durable files").
#include "flipper/record/durable_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>

#include "flipper/sdk/errors.hpp"

namespace flipper::record {
namespace {

[[noreturn]] void fail(const std::string& path, int err, const char* what = "cannot write") {
  throw sdk::Error(sdk::codes::kWriteFailed,
                   std::string(what) + " '" + path + "': " + std::strerror(err));
}

// Writes all of `text` to `fd`; the errno of the first failure, 0 when all of it was written.
int write_all(int fd, std::string_view text) {
  while (!text.empty()) {
    const ssize_t n = ::write(fd, text.data(), text.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    if (n == 0) return EIO;
    text.remove_prefix(static_cast<std::size_t>(n));
  }
  return 0;
}

// fsync of the folder holding `path`: the rename that replaced the file is then on the disk.
int sync_folder(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  const std::filesystem::path dir = parent.empty() ? std::filesystem::path(".") : parent;
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return errno;
  const int err = ::fsync(fd) == 0 || errno == EINVAL ? 0 : errno;
  ::close(fd);
  return err;
}

}  // namespace

void write_file_atomically(const std::string& path, std::string_view content, unsigned mode) {
  const std::string temp = path + ".tmp";
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW,
                        static_cast<mode_t>(mode));
  if (fd < 0) fail(path, errno);
  int err = write_all(fd, content);
  if (err == 0 && ::fsync(fd) != 0) err = errno;
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err == 0 && ::rename(temp.c_str(), path.c_str()) != 0) err = errno;
  if (err != 0) {
    ::unlink(temp.c_str());
    fail(path, err);
  }
  if ((err = sync_folder(path)) != 0) fail(path, err, "cannot sync the folder of");
}

AppendFile::AppendFile(std::string path, unsigned mode) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, static_cast<mode_t>(mode));
  if (fd_ < 0) fail(path_, errno, "cannot open for appending");
}

AppendFile::AppendFile(AppendFile&& other) noexcept
    : path_(std::move(other.path_)), fd_(std::exchange(other.fd_, -1)) {}

AppendFile& AppendFile::operator=(AppendFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(other.path_);
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

AppendFile::~AppendFile() {
  if (fd_ >= 0) ::close(fd_);
}

void AppendFile::append(std::string_view text) {
  if (fd_ < 0) fail(path_, EBADF);
  struct stat before {};
  const bool sized = ::fstat(fd_, &before) == 0 && S_ISREG(before.st_mode);
  const int err = write_all(fd_, text);
  if (err == 0) return;
  // Take a partial line back: the file ends with the last whole line, as before the call.
  if (sized) (void)::ftruncate(fd_, before.st_size);
  fail(path_, err);
}

void AppendFile::sync() {
  if (fd_ < 0) fail(path_, EBADF);
  if (::fdatasync(fd_) != 0 && errno != EINVAL) fail(path_, errno, "cannot sync");
}

}  // namespace flipper::record
