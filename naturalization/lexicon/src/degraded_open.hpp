#pragma once
// Opening a store that cannot be written (docs/naturalization.md §5 "Store faults"): a store on a
// read-only file system, a read-only file or folder, or a full device still serves its rules.
#include <memory>
#include <string>

#include "flipper/sdk/errors.hpp"
#include "sqlite_handle.hpp"

namespace flipper::naturalization {

/// Why an existing store whose read-write open failed with `error` can still be read, as the
/// code its writes are refused with: lexicon_read_only (the file, its folder or its file system
/// is read-only) or lexicon_full (no space left). Null when the failure has another cause (a
/// corrupt or foreign file, a busy store, ...), which is then reported as it is.
const char* degraded_reason(const std::string& path, const sdk::Error& error);

/// Opens `path` for reading only. SQLite's WAL mode needs its shared-memory index (`-shm`), which
/// cannot be created in a read-only folder or on a full device: when the WAL holds no frames the
/// file alone is the whole store, and it is opened as immutable (no locks, no index; commits by
/// other processes after this open are not seen). A WAL with frames needs its index: then the
/// store is opened read-only through it, and refused (with the original cause) when that fails.
std::unique_ptr<sqlite::Db> open_for_reading(const std::string& path, int busy_timeout_ms,
                                             const sdk::Error& cause);

}  // namespace flipper::naturalization
