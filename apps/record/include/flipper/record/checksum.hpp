#pragma once
/// @file checksum.hpp
/// SHA-256 of files and texts (libsodium), as lowercase hex: how a run's manifest names the exact
/// plugins, corpus and input files it used (docs/experiments.md §2).

#include <string>

namespace flipper::record {

/// SHA-256 of a file's bytes. Throws sdk::Error(bad_request) naming
/// the file when it cannot be read.
std::string sha256_file(const std::string& path);
/// SHA-256 of a text.
std::string sha256_text(const std::string& text);

}  // namespace flipper::record
