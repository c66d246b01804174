// Durable files (docs/experiments.md "Durable files"): an atomic replacement and a checked append
// that a full device (/dev/full) or a file-size limit (RLIMIT_FSIZE, standing in for a full
// file system) turn into write_failed naming the file, with the previous content kept byte for
// byte and no temporary left behind.
#include <sys/resource.h>

#include <catch2/catch.hpp>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "flipper/record/durable_file.hpp"
#include "flipper/sdk/errors.hpp"
#include "record_scratch.hpp"

namespace {

namespace fs = std::filesystem;
using flipper::record::AppendFile;
using flipper::record::write_file_atomically;

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Files may grow to `bytes` while it lives (writes beyond fail with EFBIG, not SIGXFSZ).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    previous_signal_ = std::signal(SIGXFSZ, SIG_IGN);
    REQUIRE(::getrlimit(RLIMIT_FSIZE, &previous_) == 0);
    rlimit limit = previous_;
    limit.rlim_cur = bytes;
    REQUIRE(::setrlimit(RLIMIT_FSIZE, &limit) == 0);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &previous_);
    std::signal(SIGXFSZ, previous_signal_);
  }

 private:
  rlimit previous_{};
  void (*previous_signal_)(int) = nullptr;
};

// The write_failed message of `f`, or "" when it did not throw write_failed.
template <class F>
std::string write_failure(F&& f) {
  try {
    f();
  } catch (const flipper::sdk::Error& e) {
    if (e.code() == std::string("write_failed")) return e.what();
    return std::string("other code: ") + e.code();
  }
  return {};
}

TEST_CASE("an atomic write replaces the file whole, or keeps the old one when the disk is full") {
  const fs::path dir = recordtest::scratch("durable-atomic");
  const std::string path = (dir / "state.json").string();
  write_file_atomically(path, "old content\n");
  CHECK(read_file(path) == "old content\n");
  const std::string big(3000, 'x');
  {
    const FileSizeLimit limit(2999);  // one byte short of the new content
    const std::string message = write_failure([&] { write_file_atomically(path, big); });
    CHECK(message == "cannot write '" + path + "': File too large");
  }
  CHECK(read_file(path) == "old content\n");
  CHECK_FALSE(fs::exists(path + ".tmp"));
  {
    const FileSizeLimit limit(3000);  // exactly enough
    write_file_atomically(path, big);
  }
  CHECK(read_file(path) == big);
  CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 1);
}

TEST_CASE("an atomic write into a folder that is missing names the file") {
  const fs::path dir = recordtest::scratch("durable-missing");
  const std::string path = (dir / "no" / "state.json").string();
  CHECK(write_failure([&] { write_file_atomically(path, "x"); }) ==
        "cannot write '" + path + "': No such file or directory");
}

TEST_CASE("an append to a full device fails with write_failed naming it") {
  AppendFile full("/dev/full");
  CHECK(write_failure([&] { full.append("a line\n"); }) ==
        "cannot write '/dev/full': No space left on device");
}

TEST_CASE("an append that does not fit is taken back: the file ends with its last whole line") {
  const fs::path dir = recordtest::scratch("durable-append");
  const std::string path = (dir / "log.jsonl").string();
  AppendFile log(path);
  log.append("first line\n");  // 11 bytes
  const std::string second(20, 'b');
  {
    const FileSizeLimit limit(11 + 21);  // exactly the second line and its newline
    log.append(second + "\n");
    CHECK(write_failure([&] { log.append("c\n"); }) ==
          "cannot write '" + path + "': File too large");
  }
  CHECK(read_file(path) == "first line\n" + second + "\n");
  {
    // Room for part of the line only: the part written is truncated away.
    const FileSizeLimit limit(32 + 5);
    CHECK_FALSE(write_failure([&] { log.append("a longer third line\n"); }).empty());
  }
  CHECK(read_file(path) == "first line\n" + second + "\n");
  log.append("third\n");  // the limit is gone: appends work again
  log.sync();
  CHECK(read_file(path) == "first line\n" + second + "\nthird\n");
}

TEST_CASE("an append file that cannot be opened is write_failed at once") {
  const fs::path dir = recordtest::scratch("durable-open");
  const std::string path = (dir / "missing" / "log.jsonl").string();
  CHECK(write_failure([&] { AppendFile f(path); }) ==
        "cannot open for appending '" + path + "': No such file or directory");
}

}  // namespace
