// Guards for known findings (see known_findings.hpp).
#include "known_findings.hpp"

#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace flipper::fuzz::known {

namespace {

constexpr std::array<const char*, static_cast<int>(Class::kCount)> kNames = {
    "bad_json_utf8", "huge_number", "deep_json",  "long_line",
    "parse_budget",  "huge_world",  "non_regular"};

struct Counters {
  std::array<unsigned long, static_cast<int>(Class::kCount)> skipped{};
  ~Counters() {
    for (std::size_t i = 0; i < skipped.size(); ++i)
      if (skipped[i] != 0)
        std::fprintf(stderr, "flipper fuzz: skipped %lu inputs of known class %s\n", skipped[i],
                     kNames[i]);
  }
};

Counters& counters() {
  static Counters c;
  return c;
}

}  // namespace

bool enabled() {
  static const bool on = [] {
    const char* v = std::getenv("FLIPPER_FUZZ_KNOWN");
    return v == nullptr || std::strcmp(v, "0") != 0;
  }();
  return on;
}

bool skip(Class c) {
  if (!enabled()) return false;
  ++counters().skipped[static_cast<int>(c)];
  return true;
}

bool has_invalid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    int extra = 0;
    unsigned min = 0;
    unsigned cp = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xE0) == 0xC0) {
      extra = 1, min = 0x80, cp = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      extra = 2, min = 0x800, cp = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      extra = 3, min = 0x10000, cp = c & 0x07;
    } else {
      return true;
    }
    if (i + static_cast<std::size_t>(extra) >= s.size()) return true;  // truncated sequence
    for (int k = 1; k <= extra; ++k) {
      const auto d = static_cast<unsigned char>(s[i + static_cast<std::size_t>(k)]);
      if ((d & 0xC0) != 0x80) return true;
      cp = (cp << 6) | (d & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return true;
    i += static_cast<std::size_t>(extra) + 1;
  }
  return false;
}

bool has_non_ascii(std::string_view s) {
  for (char c : s)
    if (static_cast<unsigned char>(c) >= 0x80) return true;
  return false;
}

bool has_huge_number(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    if (!std::isdigit(static_cast<unsigned char>(s[i]))) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.')) ++j;
    if (j < s.size() && (s[j] == 'e' || s[j] == 'E')) {
      ++j;
      if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
      while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
    }
    const std::string literal(s.substr(i, j - i));
    if (std::isinf(std::strtod(literal.c_str(), nullptr))) return true;
    i = j;
  }
  return false;
}

bool nesting_deeper_than(std::string_view s, int limit) {
  int depth = 0;
  for (char c : s) {
    if (c == '[' || c == '{') {
      if (++depth > limit) return true;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return false;
}

bool more_words_than(std::string_view s, int limit) {
  int words = 0;
  bool in_word = false;
  for (char c : s) {
    const bool space = std::isspace(static_cast<unsigned char>(c)) != 0;
    if (!space && !in_word && ++words > limit) return true;
    in_word = !space;
  }
  return false;
}

bool names_special_path(std::string_view s) {
  return s.find("/dev") != std::string_view::npos || s.find("/proc") != std::string_view::npos ||
         s.find("/sys") != std::string_view::npos;
}

}  // namespace flipper::fuzz::known
