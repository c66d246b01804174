// Bounded request-line reading (see request_lines.hpp).
#include "request_lines.hpp"

namespace flipper::cli {

LineRead read_request_line(std::istream& in, std::uint64_t max_bytes, std::string& out,
                           std::uint64_t& bytes) {
  out.clear();
  bytes = 0;
  std::streambuf* sb = in.rdbuf();
  using Traits = std::char_traits<char>;
  for (;;) {
    const Traits::int_type c = sb->sbumpc();
    if (Traits::eq_int_type(c, Traits::eof())) {
      in.setstate(std::ios::eofbit);
      if (bytes == 0) return LineRead::eof;
      break;
    }
    if (Traits::to_char_type(c) == '\n') break;
    if (++bytes <= max_bytes) {
      out.push_back(Traits::to_char_type(c));
    } else if (bytes == max_bytes + 1) {
      std::string().swap(out);  // give the memory back: the rest is only counted
    }
  }
  return bytes > max_bytes ? LineRead::too_long : LineRead::line;
}

}  // namespace flipper::cli
