#pragma once
// The study recording's whole-file JSON state (docs/studio.md §7: participants.json,
// sessions.json, study.json): read at start, rewritten atomically (record::write_file_atomically:
// checked writes, fsync, rename, fsync of the folder), so a reader, a restart or a full disk never
// leaves half a file.
#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace flipper::studio {

/// The JSON document of `path`; nullopt when the file does not exist or cannot be opened, a
/// discarded value (is_discarded()) when it is not JSON.
std::optional<nlohmann::json> read_json_file(const std::string& path);

/// Writes `value` (indent 1) to `path` atomically. Throws sdk::Error(write_failed) naming the
/// file when it cannot be written; the previous file stays.
void write_json_file(const std::string& path, const nlohmann::json& value);

}  // namespace flipper::studio
