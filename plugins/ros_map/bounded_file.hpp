#pragma once
/// @file bounded_file.hpp
/// Reading a file a world names (map YAML, PGM image) with a size bound: a regular file only
/// (a FIFO or device would block or never end), at most `max_bytes` bytes, read whole.
#include <cstdint>
#include <string>

namespace flipper::plugins::ros_map {

/// The file's bytes. Throws sdk::Error: bad_world (missing, unreadable, changed while read),
/// not_a_regular_file, file_too_large; each message starts with `what` and names the path (and
/// `limit_name`, the limit's param or key).
std::string read_bounded_file(const std::string& path, std::uint64_t max_bytes,
                              const std::string& what, const char* limit_name = "max_file_bytes");

}  // namespace flipper::plugins::ros_map
