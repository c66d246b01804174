#include "flipper/dds/lexicon_event.hpp"

namespace flipper::dds {
namespace {
constexpr std::size_t kMaxName = 256;
constexpr std::size_t kMaxText = 1 << 16;
constexpr std::size_t kMaxWorld = 1 << 24;
constexpr std::size_t kMaxLines = 1000;

bool printable_name(const std::string& s) {
  if (s.empty() || s.size() > kMaxName) return false;
  for (unsigned char c : s)
    if (c < 0x20 || c == 0x7f) return false;
  return true;
}
}  // namespace

std::optional<std::string> malformed(const LexiconEvent& e) {
  if (!printable_name(e.site)) return "site must be 1..256 printable bytes";
  if (e.version == 0) return "version must be positive";
  if (!printable_name(e.author)) return "author must be 1..256 printable bytes";
  if (e.kind == "define") {
    if (e.head.empty() || e.head.size() > kMaxText) return "head must be 1..65536 bytes";
    if (e.body.empty() || e.body.size() > kMaxLines) return "body must have 1..1000 lines";
    for (const auto& line : e.body)
      if (line.size() > kMaxText) return "a body line is longer than 65536 bytes";
    if (!e.ranks.empty() && e.ranks.size() != e.body.size())
      return "ranks must be empty or one per body line";
    if (e.world.size() > kMaxWorld) return "world is larger than 16 MiB";
    return std::nullopt;
  }
  if (e.kind == "delete") {
    if (!printable_name(e.target_site)) return "a deletion needs target_site";
    if (e.target_version == 0) return "a deletion needs target_version";
    return std::nullopt;
  }
  return "kind must be 'define' or 'delete', not '" + e.kind.substr(0, 32) + "'";
}

}  // namespace flipper::dds
