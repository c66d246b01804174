#pragma once
/// @file regular_file.hpp
/// Reading files that cannot be FIFOs, devices or huge (docs/bad-input.md): a config document,
/// and the kernel's world, grammar and preload files under input.max_file_bytes.

#include <cstdint>
#include <string>

namespace flipper::toolkit::config {

/// Reads a whole file that must be a regular file (not a FIFO, device or directory) of at most
/// `max_bytes` bytes; `what` names it in messages ("world file"). Throws sdk::Error with
/// `not_a_regular_file`, `file_too_large`, or `missing_code` when it cannot be opened/read.
/// The size is checked on the open descriptor, and reading stops at max_bytes + 1 regardless,
/// so a file that grows meanwhile cannot make it read more.
std::string read_regular_file(const std::string& path, std::uint64_t max_bytes,
                              const std::string& what, const char* missing_code);

/// Checks the same for a file another library will read (e.g. an OctoMap .bt) without reading it.
void check_regular_file(const std::string& path, std::uint64_t max_bytes, const std::string& what,
                        const char* missing_code);

}  // namespace flipper::toolkit::config
