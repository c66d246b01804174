#pragma once
// A look at a WAL-mode store's shared-memory index without a system call (docs/naturalization.md
// §5 "Many writers"): every commit, by any connection of any process, rewrites
// the WAL-index header at the start of the index, so a header equal to the one seen at the last
// `PRAGMA data_version` means nothing was committed since, and the pragma (a read transaction:
// two fcntl lock calls and a stat, several µs on a virtual machine) can be skipped. Any doubt (no
// index, a header that is not SQLite's version 3007000 or not initialised, its two copies
// differing because a writer is updating it) reads as "maybe changed": the caller then asks
// SQLite as before.
//
// The index is the one SQLite's connection has mapped (the VFS's xShmMap of region 0, which stays
// mapped while the connection is open in WAL mode): no file of our own is opened, because closing
// any descriptor of a file drops every POSIX lock the process holds on it, SQLite's included.
#include <sqlite3.h>

#include <array>
#include <optional>

namespace flipper::naturalization {

class WalIndexWatch {
 public:
  /// The header of a WAL index: its first copy's 48 bytes (https://sqlite.org/walformat.html,
  /// "The WAL-Index Header").
  using Header = std::array<unsigned char, 48>;

  /// Takes `db`'s mapping of its main database's WAL index; false when there is none (an
  /// in-memory store, a VFS without shared memory). Call it only for a connection open for
  /// writing in WAL mode that has read the store (SQLite maps the index on the first read), and
  /// keep the watch no longer than the connection.
  bool map(sqlite3* db);

  /// The header now, when it can be trusted: mapped, initialised, SQLite's WAL-index version,
  /// both copies equal.
  std::optional<Header> read() const;

 private:
  const volatile unsigned char* base_ = nullptr;
};

}  // namespace flipper::naturalization
