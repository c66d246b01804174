// The login rate limit (docs/accounts.md §2): ten attempts per address, the eleventh refused with
// 429 `login_rate_limited` and Retry-After, other addresses unaffected. Each attempt comes on its
// own connection from a chosen loopback source address (raw_socket.hpp).
#include <chrono>
#include <regex>

#include "raw_socket.hpp"
#include "studio_server.hpp"

namespace flipper::studiotest {
namespace {

using namespace std::chrono_literals;

struct LoginAnswer {
  int status = 0;
  std::string code;         ///< error.code, "" on success
  std::string retry_after;  ///< the Retry-After header, "" when absent
};

LoginAnswer login_from(const StudioServer& server, const std::string& source,
                       const std::string& body) {
  RawSocket s(server.port(), source);
  REQUIRE(s.connected());
  REQUIRE(s.send("POST /api/v1/login HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(server.port()) +
                 "\r\nContent-Type: application/json\r\nContent-Length: " +
                 std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body));
  // Bound: at most one Argon2id check (~0.1 s in Release, ~1 s on a loaded machine).
  const std::string reply = s.read_all(30s);
  INFO(reply);
  std::smatch m;
  REQUIRE(std::regex_search(reply, m, std::regex("^HTTP/1\\.1 (\\d{3}) ")));
  LoginAnswer a;
  a.status = std::stoi(m[1]);
  if (std::regex_search(reply, m, std::regex("\r\nRetry-After: *([^\r]*)\r\n", std::regex::icase)))
    a.retry_after = m[1];
  const json j = json::parse(reply.substr(reply.find("\r\n\r\n") + 4), nullptr, false);
  if (j.is_object() && j.contains("error")) a.code = j["error"]["code"].get<std::string>();
  return a;
}

const std::string kRight = json{{"name", "ana"}, {"password", "ana's password"}}.dump();

}  // namespace

TEST_CASE("the eleventh login from one address is refused with Retry-After, others go on") {
  StudioServer server(fresh_dir("login-limit"));
  server.add_account("ana", "ana's password");
  // Every attempt counts, a malformed one too: ten without a body's fields (400, no password
  // check, so the ten take ~50 ms in Release) use up 127.0.0.1's bucket of ten.
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 10; ++i) {
    INFO("attempt " << i + 1);
    const LoginAnswer a = login_from(server, "127.0.0.1", "{}");
    CHECK(a.status == 400);
    CHECK(a.code == "missing_field");
    CHECK(a.retry_after.empty());
  }
  // The 11th, with the right password: refused before any check.
  const LoginAnswer refused = login_from(server, "127.0.0.1", kRight);
  const double spent =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  INFO("the eleven attempts took " << spent << " s");
  CHECK(refused.status == 429);
  CHECK(refused.code == "login_rate_limited");
  // One attempt comes back every 6 s: after `spent` seconds the next is (6 - spent) s away,
  // rounded up. 5 or 6 while the eleven take under 1 s (their cost is ~50 ms in Release; the
  // sanitizer build is ~4x slower: 1 s is ~5x that).
  REQUIRE(std::regex_match(refused.retry_after, std::regex("[0-9]+")));
  CHECK(std::stoi(refused.retry_after) >= 5);
  CHECK(std::stoi(refused.retry_after) <= 6);
  CHECK(login_from(server, "127.0.0.1", "{}").code == "login_rate_limited");  // and the 12th
  // Other addresses have buckets of their own.
  const LoginAnswer other = login_from(server, "127.0.0.2", kRight);
  CHECK(other.status == 200);
  CHECK(other.retry_after.empty());
  CHECK(login_from(server, "127.0.0.3", "{}").code == "missing_field");
}

}  // namespace flipper::studiotest
