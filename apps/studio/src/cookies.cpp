#include "cookies.hpp"

#include <cctype>

namespace flipper::studio {
namespace {

constexpr const char* kCookie = "flipper_login";

}  // namespace

std::string login_cookie(const std::string& header) {
  // "a=1; flipper_login=TOKEN; b=2"
  std::size_t at = 0;
  while (at < header.size()) {
    while (at < header.size() && (header[at] == ' ' || header[at] == ';')) ++at;
    const auto end = header.find(';', at);
    const std::string pair = header.substr(at, end == std::string::npos ? end : end - at);
    const auto eq = pair.find('=');
    if (eq != std::string::npos && pair.substr(0, eq) == kCookie) return pair.substr(eq + 1);
    if (end == std::string::npos) break;
    at = end + 1;
  }
  return {};
}

std::string login_cookie_header(const std::string& token, std::chrono::seconds valid_for) {
  return std::string(kCookie) + "=" + token +
         "; Path=/; HttpOnly; SameSite=Strict; Max-Age=" + std::to_string(valid_for.count());
}

std::string login_cookie_cleared() {
  return std::string(kCookie) + "=; Path=/; HttpOnly; SameSite=Strict; Max-Age=0";
}

std::string header_safe(const std::string& name) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '.' || c == '_' || c == '-') {
      out.push_back(c);
    } else {
      out.push_back('%');
      out.push_back(kHex[u >> 4]);
      out.push_back(kHex[u & 15]);
    }
  }
  return out;
}

}  // namespace flipper::studio
