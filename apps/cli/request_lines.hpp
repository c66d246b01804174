#pragma once
/// @file request_lines.hpp
/// Reading request lines without trusting their length: a line longer than the limit is skipped
/// up to its newline without being kept, so a 68 MB line costs no more memory than the limit.
/// The pipe front end's job (`flipper session`, docs/protocol.md): the kernel's session answers a
/// line it is given (Session::handle_line, Session::line_too_long).

#include <cstdint>
#include <istream>
#include <string>

namespace flipper::cli {

enum class LineRead {
  line,      ///< `out` holds the line (without the newline)
  too_long,  ///< the line had more than `max_bytes` bytes; `bytes` says how many, `out` is empty
  eof,       ///< nothing left
};

/// Reads one line of at most `max_bytes` bytes from `in` (a final line without a newline counts).
LineRead read_request_line(std::istream& in, std::uint64_t max_bytes, std::string& out,
                           std::uint64_t& bytes);

}  // namespace flipper::cli
