#pragma once
/// @file out_file.hpp
/// An output file whose write errors are reported: a full device makes close() throw
/// sdk::Error(write_failed) naming the file and the system's reason, instead of a short file.
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <string>

#include "flipper/sdk/errors.hpp"

namespace flipper::record {

class OutFile {
 public:
  explicit OutFile(std::string path) : path_(std::move(path)), out_(path_) {
    if (!out_) fail();
    out_ << std::setprecision(6);
  }
  OutFile(const OutFile&) = delete;
  OutFile& operator=(const OutFile&) = delete;

  template <class T>
  std::ostream& operator<<(const T& value) {
    return out_ << value;
  }
  std::ostream& stream() { return out_; }
  /// Flushes and closes; throws write_failed when any write did not reach the file.
  void close() {
    out_.flush();
    if (!out_) fail();
    out_.close();
    if (!out_) fail();
  }

 private:
  [[noreturn]] void fail() {
    const int err = errno;
    throw sdk::Error(sdk::codes::kWriteFailed,
                     "cannot write '" + path_ + "'" +
                         (err != 0 ? std::string(": ") + std::strerror(err) : std::string()));
  }
  std::string path_;
  std::ofstream out_;
};

}  // namespace flipper::record
