#pragma once
/// @file durable_file.hpp
/// The one way the recorder, the studio and the run records change a file (docs/experiments.md
/// "Durable files"): a whole file is replaced atomically (a temporary beside it, every write
/// checked, fsync, rename over the old one, fsync of the folder), and a log grows by whole lines
/// (every write checked; a line that does not fit is taken back). Either way a full device, a
/// file-size limit or an I/O error throws sdk::Error(write_failed) naming the file and the
/// system's reason, and the previous good content stays as it was.
#include <string>
#include <string_view>

namespace flipper::record {

/// Replaces `path` by `content` atomically: a reader or a crash sees the old file or the new
/// one, never a mix or a short file. Throws write_failed (the old file untouched, no temporary
/// left behind).
void write_file_atomically(const std::string& path, std::string_view content, unsigned mode = 0644);

/// A file opened for appending (created with `mode` when missing). Move-only; closed on
/// destruction.
class AppendFile {
 public:
  AppendFile() = default;
  /// Throws write_failed when the file cannot be opened for appending.
  explicit AppendFile(std::string path, unsigned mode = 0644);
  AppendFile(AppendFile&& other) noexcept;
  AppendFile& operator=(AppendFile&& other) noexcept;
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;
  ~AppendFile();

  /// Appends `text` whole, or throws write_failed and leaves the file as it was before the
  /// call (a partial write is truncated away). Not synchronised: one writer at a time. The data
  /// is in the system's cache when this returns (it survives the process, not a power loss;
  /// sync() for that).
  void append(std::string_view text);
  /// fdatasync: what was appended survives a power loss. Throws write_failed.
  void sync();
  bool is_open() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace flipper::record
