#pragma once
/// @file fuzz_support.hpp
/// Helpers shared by the libFuzzer targets in fuzz/: splitting inputs, a private scratch
/// directory, and the repository root.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace flipper::fuzz {

/// The fuzz input as text.
inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// Splits at '\n' (a trailing '\r' stays part of the line), at most `max_parts` parts; the last
/// part keeps the rest.
std::vector<std::string_view> split_lines(std::string_view text, std::size_t max_parts);

/// Splits at lines that are exactly `marker` (e.g. "%%"), at most `max_parts` parts.
std::vector<std::string_view> split_sections(std::string_view text, std::string_view marker,
                                             std::size_t max_parts);

/// A directory of this process (created on first use under $TMPDIR, removed at exit).
const std::string& scratch_dir();

/// Writes `text` to `path` (truncating). Aborts when the file cannot be written: the target
/// would otherwise test nothing.
void write_file(const std::string& path, std::string_view text);

/// The repository root (the source tree the fuzz target was built from).
std::string source_dir();

}  // namespace flipper::fuzz
