#pragma once
// Strings of every kind of byte for JSON writer tests: ASCII, the escaped ones, control
// characters, valid multi-byte UTF-8, and bytes that are not UTF-8 (replaced by U+FFFD).
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace flipper::testsupport {

inline std::string random_string(std::mt19937_64& rng) {
  static const std::vector<std::string> pieces = {
      "a",    "Z",     " ",    "\"",       "\\",       "/",
      "\n",   "\t",    "\r",   "\b",       "\f",       std::string(1, '\0'),
      "\x01", "\x1f",  "\x7f", "é",        "ünï",      "€",
      "😀",    "\xff",  "\xc3", "\xe2\x82", "\xf0\x9f", "\xed\xa0\x80",
      "red",  "circle"};
  std::string s;
  const auto n = rng() % 8;
  for (std::uint64_t i = 0; i < n; ++i) s += pieces[rng() % pieces.size()];
  return s;
}

}  // namespace flipper::testsupport
