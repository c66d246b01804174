// Original pretty text -> canonical text (see original_text.hpp).
#include "flipper/corpus/original_text.hpp"

#include <regex>

namespace flipper::corpus {

std::string normalize_original_pretty(std::string s) {
  static const std::regex dot_zero(R"((-?\d+)\.0\b)");
  static const std::regex number(R"(\(number (-?[0-9.]+)\))");
  static const std::regex arith(R"(\(([+-]) (\{[^{}()]*\}|[^\s()]+) (\{[^{}()]*\}|[^\s()]+)\))");
  s = std::regex_replace(s, dot_zero, "$1");
  s = std::regex_replace(s, number, "$1");
  for (std::string prev; prev != s;) {
    prev = s;
    s = std::regex_replace(s, arith, "{$2 $1 $3}");
  }
  // `{item at <filter><location>}`: the filter, if any, is a braced group followed by more text.
  const std::string key = "{item at ";
  for (std::size_t p = s.find(key); p != std::string::npos; p = s.find(key, p + 1)) {
    std::size_t q = p + key.size();
    if (q >= s.size() || s[q] != '{') continue;
    int depth = 0;
    std::size_t e = q;
    for (; e < s.size(); ++e) {
      if (s[e] == '{') ++depth;
      if (s[e] == '}' && --depth == 0) break;
    }
    if (e + 1 >= s.size() || s[e + 1] == '}') continue;  // `{item at {room3 or room1}}`
    const std::string filter = s.substr(q, e + 1 - q);
    s = s.substr(0, p) + "{item " + filter + " at " + s.substr(e + 1);
  }
  return s;
}

}  // namespace flipper::corpus
