#include "flipper/dds/lexicon_event.hpp"

#include <stdexcept>

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

namespace {

std::string hex(const std::string& bytes) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (unsigned char c : bytes) {
    out += digits[c >> 4];
    out += digits[c & 15];
  }
  return out;
}

std::string unhex(const std::string& text) {
  if (text.size() % 2 != 0) throw std::invalid_argument("odd hex length");
  std::string out;
  for (std::size_t i = 0; i < text.size(); i += 2)
    out += static_cast<char>(std::stoi(text.substr(i, 2), nullptr, 16));
  return out;
}

nlohmann::json content(const LexiconEvent& e) {
  return nlohmann::json{{"site", e.site},
                        {"version", e.version},
                        {"kind", e.kind},
                        {"lamport", e.lamport},
                        {"time", e.time},
                        {"author", e.author},
                        {"head", e.head},
                        {"body", e.body},
                        {"ranks", e.ranks},
                        {"world", e.world},
                        {"rules", e.rules},
                        {"target_site", e.target_site},
                        {"target_version", e.target_version},
                        {"target_rule", e.target_rule}};
}

}  // namespace

nlohmann::json to_json(const LexiconEvent& e) {
  nlohmann::json j = content(e);
  j["certificate"] = e.certificate;
  j["signature"] = hex(e.signature);
  return j;
}

LexiconEvent event_from_json(const nlohmann::json& j) {
  LexiconEvent e;
  e.site = j.at("site");
  e.version = j.at("version");
  e.kind = j.at("kind");
  e.lamport = j.at("lamport");
  e.time = j.at("time");
  e.author = j.at("author");
  e.head = j.at("head");
  e.body = j.at("body").get<std::vector<std::string>>();
  e.ranks = j.at("ranks").get<std::vector<int>>();
  e.world = j.at("world");
  e.rules = j.at("rules").get<std::vector<std::string>>();
  e.target_site = j.at("target_site");
  e.target_version = j.at("target_version");
  e.target_rule = j.at("target_rule");
  e.certificate = j.value("certificate", "");  // logs written before signatures existed
  e.signature = unhex(j.value("signature", ""));
  return e;
}

std::string signed_text(const LexiconEvent& e) {
  return content(e).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace flipper::dds
