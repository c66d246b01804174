#pragma once
// The login cookie and header-safe names of the studio's HTTP answers (docs/accounts.md).
#include <chrono>
#include <string>

namespace flipper::studio {

/// The login token in a Cookie header ("" when none).
std::string login_cookie(const std::string& cookie_header);
/// The Set-Cookie value of a login.
std::string login_cookie_header(const std::string& token, std::chrono::seconds valid_for);
/// The Set-Cookie value that ends the login cookie in the browser.
std::string login_cookie_cleared();
/// A header-safe form of a name: anything but letters, digits, '.', '_' and '-' as %XX.
std::string header_safe(const std::string& name);

}  // namespace flipper::studio
