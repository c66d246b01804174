// HTTPS and proxies (docs/serve.md "HTTPS", "Behind a proxy"): `flipper serve` with
// serve.tls.cert/key answers over TLS with a test CA's certificate (made at test time by
// make-test-pki), its cookies are Secure whenever the page is HTTPS, plain HTTP to its port is
// told so and closed, bad TLS files stop it with exit 2 naming the file; serve.behind_proxy
// takes the client address and scheme from X-Forwarded-* of listed peers only.
#include <chrono>
#include <regex>

#include "proxy_policy.hpp"
#include "raw_socket.hpp"
#include "studio_server.hpp"

namespace flipper::studiotest {
namespace {

using namespace std::chrono_literals;

/// The test PKI in a fresh directory (tests/apps/studio/make-test-pki).
std::string make_pki(const std::string& name) {
  std::string dir = fresh_dir(name);
  const CliRun made = run_shell("bash " + std::string(FLIPPER_SOURCE_DIR) +
                                "/tests/apps/studio/make-test-pki " + dir + " 2>&1");
  INFO(made.out);
  REQUIRE(made.status == 0);
  return dir;
}

std::vector<std::string> tls_sets(const std::string& pki) {
  return {"serve.tls.cert=" + pki + "/server.pem", "serve.tls.key=" + pki + "/server.key"};
}

/// An HTTPS client that trusts the test CA only (and checks the name, 127.0.0.1).
std::unique_ptr<httplib::SSLClient> https_client(const StudioServer& server,
                                                 const std::string& ca) {
  auto c = std::make_unique<httplib::SSLClient>("127.0.0.1", server.port());
  c->set_ca_cert_path(ca.c_str());
  c->enable_server_certificate_verification(true);
  c->set_connection_timeout(10);
  c->set_read_timeout(30);
  return c;
}

const std::string kAna = json{{"name", "ana"}, {"password", "ana's password"}}.dump();
// serve.login_days = 30.
const std::string kCookieTail = "; Path=/; HttpOnly; SameSite=Strict; Max-Age=2592000";

/// One request on its own connection from `source` (a loopback address): status, the
/// Set-Cookie header ("" when none) and the body.
struct RawAnswer {
  int status = 0;
  std::string set_cookie;
  json body;
};
RawAnswer raw_post(int port, const std::string& source, const std::string& path,
                   const std::string& body, const std::string& extra_headers,
                   const std::string& host = "") {
  RawSocket s(port, source);
  REQUIRE(s.connected());
  REQUIRE(s.send(
      "POST " + path +
      " HTTP/1.1\r\nHost: " + (host.empty() ? "127.0.0.1:" + std::to_string(port) : host) +
      "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
      "\r\nConnection: close\r\n" + extra_headers + "\r\n" + body));
  // Bound: one request (an Argon2id check for a login, ~1 s on a loaded machine).
  const std::string reply = s.read_all(30s);
  INFO(reply);
  std::smatch m;
  REQUIRE(std::regex_search(reply, m, std::regex("^HTTP/1\\.1 (\\d{3}) ")));
  RawAnswer a;
  a.status = std::stoi(m[1]);
  if (std::regex_search(reply, m, std::regex("\r\nSet-Cookie: *([^\r]*)\r\n", std::regex::icase)))
    a.set_cookie = m[1];
  a.body = json::parse(reply.substr(reply.find("\r\n\r\n") + 4), nullptr, false);
  return a;
}

std::string error_code(const json& body) {
  return body.is_object() && body.contains("error") ? body["error"].value("code", "") : "";
}

/// A new session's request from `source` carrying `headers`: the status and error code.
std::pair<int, std::string> new_session_from(int port, const std::string& source,
                                             const std::string& headers) {
  const RawAnswer a = raw_post(port, source, "/api/v1/request", R"({"op":"state"})", headers);
  return {a.status, error_code(a.body)};
}

}  // namespace

TEST_CASE("a login over HTTPS sets a Secure cookie that works over HTTPS", "[tls]") {
  const std::string pki = make_pki("tls-pki");
  StudioServer server(fresh_dir("tls-login"), tls_sets(pki));
  server.add_account("ana", "ana's password");
  auto https = https_client(server, pki + "/ca.pem");
  auto res = https->Post("/api/v1/login", kAna, "application/json");
  REQUIRE(res);
  CHECK(res->status == 200);
  const std::string set = res->get_header_value("Set-Cookie");
  const std::string token = set.substr(0, set.find(';'));
  CHECK(token.size() == std::string("flipper_login=").size() + 64);
  CHECK(set == token + kCookieTail + "; Secure");
  // The cookie is the login over HTTPS too, and the security headers come along.
  auto info = https->Get("/api/v1/info", {{"Cookie", token}});
  REQUIRE(info);
  CHECK(json::parse(info->body)["account"] == json{{"name", "ana"}, {"role", "user"}});
  CHECK(info->get_header_value("X-Content-Type-Options") == "nosniff");
  CHECK(info->get_header_value("Content-Security-Policy") ==
        "default-src 'none'; frame-ancestors 'none'");
  // The page's own origin is https:// now; http:// of the same name is another origin.
  const std::string own = "https://127.0.0.1:" + std::to_string(server.port());
  auto same =
      https->Post("/api/v1/logout", {{"Origin", own}, {"Cookie", token}}, "", "application/json");
  REQUIRE(same);
  CHECK(same->status == 200);
  CHECK(same->get_header_value("Set-Cookie") ==
        "flipper_login=; Path=/; HttpOnly; SameSite=Strict; Max-Age=0; Secure");
  auto plain_origin =
      https->Post("/api/v1/login", {{"Origin", server.origin()}}, kAna, "application/json");
  REQUIRE(plain_origin);
  CHECK(plain_origin->status == 403);
  // A client that does not trust the test CA gets no answer (the certificate is checked).
  httplib::SSLClient stranger("127.0.0.1", server.port());
  stranger.set_ca_cert_path((pki + "/server.pem").c_str());
  stranger.enable_server_certificate_verification(true);
  CHECK_FALSE(stranger.Get("/api/v1/info"));
}

TEST_CASE("a login over plain HTTP sets no Secure cookie", "[tls]") {
  StudioServer server(fresh_dir("tls-plain"));
  server.add_account("ana", "ana's password");
  auto http = server.client();
  auto res = http.Post("/api/v1/login", kAna, "application/json");
  REQUIRE(res);
  const std::string set = res->get_header_value("Set-Cookie");
  CHECK(set == set.substr(0, set.find(';')) + kCookieTail);
}

TEST_CASE("plain HTTP to the HTTPS port is answered 400 https_required and closed", "[tls]") {
  const std::string pki = make_pki("tls-plain-pki");
  StudioServer server(fresh_dir("tls-refuse"),
                      {tls_sets(pki)[0], tls_sets(pki)[1], "serve.request_timeout_ms=3000"});
  RawSocket s(server.port());
  REQUIRE(s.connected());
  REQUIRE(s.send("GET /api/v1/info HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(server.port()) +
                 "\r\n\r\n"));
  bool closed = false;
  const std::string text = s.read_all(10s, &closed);
  CHECK(closed);
  CHECK_THAT(text, Catch::StartsWith("HTTP/1.1 400 Bad Request\r\n") &&
                       Catch::Contains("\r\nConnection: close\r\n") &&
                       Catch::Contains("\r\nX-Content-Type-Options: nosniff\r\n"));
  CHECK_THAT(text, Catch::EndsWith("\r\n\r\n{\"error\":{\"code\":\"https_required\",\"message\":"
                                   "\"this port speaks HTTPS: use https:// "
                                   "(serve.tls.cert)\"},\"ok\":false,\"op\":null}"));
  // A connection that never starts its handshake is closed at the request deadline (3 s).
  RawSocket silent(server.port());
  REQUIRE(silent.connected());
  const auto start = std::chrono::steady_clock::now();
  bool silent_closed = false;
  CHECK(silent.read_all(20s, &silent_closed).empty());
  CHECK(silent_closed);
  CHECK(std::chrono::steady_clock::now() - start < 15s);
  // The server goes on serving HTTPS.
  auto https = https_client(server, pki + "/ca.pem");
  auto info = https->Get("/api/v1/info");
  REQUIRE(info);
  CHECK(info->status == 200);
}

TEST_CASE("bad TLS settings stop flipper serve with exit 2 naming the file", "[tls]") {
  const std::string pki = make_pki("tls-bad-pki");
  const std::string dir = fresh_dir("tls-bad");
  {
    std::ofstream garbage(dir + "/garbage.pem");
    garbage << "not a certificate\n";
  }
  REQUIRE(run_shell("openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:prime256v1 "
                    "-aes256 -pass pass:secret -out " +
                    dir + "/encrypted.key 2>&1")
              .status == 0);
  // Bounded: a check that lets a bad file through leaves a server running, killed at 30 s.
  const std::string serve = "timeout 30 " + std::string(FLIPPER_BINARY_DIR) +
                            "/bin/flipper serve --set serve.port=0 --set lexicon.path=" + dir +
                            "/lex.sqlite";
  const auto run = [&](const std::string& cert, const std::string& key) {
    std::string args = serve;
    if (!cert.empty()) args += " --set serve.tls.cert=" + cert;
    if (!key.empty()) args += " --set serve.tls.key=" + key;
    return run_shell(args + " </dev/null 2>&1");
  };
  const std::string cert = pki + "/server.pem", key = pki + "/server.key";
  const std::string prefix = "flipper serve: [bad_config] ";
  struct Case {
    std::string cert, key, message;
  };
  const std::vector<Case> cases = {
      {cert, "",
       "serve.tls.cert is set but serve.tls.key is not: HTTPS needs the certificate "
       "and its key"},
      {"", key,
       "serve.tls.key is set but serve.tls.cert is not: HTTPS needs the certificate "
       "and its key"},
      {dir + "/none.pem", key,
       "serve.tls.cert '" + dir + "/none.pem': cannot read it: No such file or directory"},
      {cert, dir + "/none.key",
       "serve.tls.key '" + dir + "/none.key': cannot read it: No such file or directory"},
      {dir + "/garbage.pem", key,
       "serve.tls.cert '" + dir + "/garbage.pem' holds no PEM certificate"},
      {key, key, "serve.tls.cert '" + key + "' holds no PEM certificate"},
      {cert, cert, "serve.tls.key '" + cert + "' holds no PEM private key"},
      {cert, pki + "/other.key",
       "serve.tls.key '" + pki + "/other.key' is not the private key of the certificate in '" +
           cert + "'"},
      {cert, dir + "/encrypted.key",
       "serve.tls.key '" + dir + "/encrypted.key' is encrypted: give the key without a passphrase"},
  };
  for (const auto& c : cases) {
    INFO(c.cert << " / " << c.key);
    const CliRun r = run(c.cert, c.key);
    CHECK(r.status == 2);
    CHECK(r.out == prefix + c.message + "\n");
  }
  const CliRun proxy =
      run_shell(serve + " --set 'serve.behind_proxy=[10.0.0.1, proxy.lan]' </dev/null 2>&1");
  CHECK(proxy.status == 2);
  CHECK(proxy.out == prefix +
                         "serve.behind_proxy: 'proxy.lan' is not an IPv4 or IPv6 address (list "
                         "each proxy's address)\n");
}

TEST_CASE("the client of a listed proxy is its X-Forwarded-For, others' headers are ignored",
          "[tls][proxy]") {
  using studio::ProxyPolicy;
  const ProxyPolicy policy({"127.0.0.1", "::ffff:10.1.1.1", "fd00::0:1"});
  std::string error;
  const auto client = [&](const std::string& peer, bool tls, const std::string& xff,
                          const std::string& proto) {
    error.clear();
    const auto c = policy.client(peer, tls, xff, proto, error);
    return c ? c->address + (c->https ? " https" : " http") : "refused: " + error;
  };
  CHECK(client("127.0.0.1", false, "10.0.0.9", "https") == "10.0.0.9 https");
  CHECK(client("127.0.0.1", false, "10.0.0.9", "HTTPS, http") == "10.0.0.9 https");
  CHECK(client("127.0.0.1", true, "10.0.0.9", "http") == "10.0.0.9 http");
  CHECK(client("127.0.0.1", true, "10.0.0.9", "") == "10.0.0.9 https");
  // Walks back over listed proxies; a client's own entries further left are not believed.
  CHECK(client("127.0.0.1", false, "6.6.6.6, 10.0.0.9, 10.1.1.1", "") == "10.0.0.9 http");
  CHECK(client("127.0.0.1", false, "10.1.1.1, 127.0.0.1", "") == "10.1.1.1 http");
  CHECK(client("127.0.0.1", false, "", "") == "127.0.0.1 http");
  CHECK(client("127.0.0.1", false, "[2001:db8::7]:4711", "") == "2001:db8::7 http");
  CHECK(client("127.0.0.1", false, "10.0.0.9:4711", "") == "10.0.0.9 http");
  CHECK(client("fd00::1", false, "10.0.0.9", "") == "10.0.0.9 http");
  CHECK(client("127.0.0.1", false, "unknown", "") ==
        "refused: X-Forwarded-For names 'unknown', which is not an address");
  // Not a listed proxy: the peer and the connection's scheme, whatever the headers say.
  CHECK(client("127.0.0.2", false, "10.0.0.9", "https") == "127.0.0.2 http");
  CHECK(client("127.0.0.2", true, "10.0.0.9", "http") == "127.0.0.2 https");
  CHECK(client("127.0.0.2", false, "unknown", "") == "127.0.0.2 http");
  CHECK(ProxyPolicy().client("127.0.0.1", false, "10.0.0.9", "https", error)->address ==
        "127.0.0.1");
}

TEST_CASE("per-address session limits count on X-Forwarded-For from a listed proxy only",
          "[tls][proxy]") {
  // 127.0.0.1 is the proxy; 127.0.0.2 is a client that sends the same headers itself.
  StudioServer server(fresh_dir("proxy-limits"),
                      {"serve.behind_proxy=[127.0.0.1]", "serve.sessions_per_address=2"});
  const int port = server.port();
  const std::string from_a = "X-Forwarded-For: 10.0.0.1\r\n";
  const std::string from_b = "X-Forwarded-For: 10.0.0.2\r\n";
  // Through the proxy: two sessions per forwarded client; the third of 10.0.0.1 is refused,
  // 10.0.0.2 is another client.
  CHECK(new_session_from(port, "127.0.0.1", from_a) == std::pair{200, std::string()});
  CHECK(new_session_from(port, "127.0.0.1", from_a) == std::pair{200, std::string()});
  CHECK(new_session_from(port, "127.0.0.1", from_a) ==
        std::pair{429, std::string("too_many_sessions")});
  CHECK(new_session_from(port, "127.0.0.1", from_b) == std::pair{200, std::string()});
  // The proxy itself (no header) is a client of its own.
  CHECK(new_session_from(port, "127.0.0.1", "") == std::pair{200, std::string()});
  // Not a listed proxy: its X-Forwarded-For is ignored, so it cannot pick fresh addresses.
  CHECK(new_session_from(port, "127.0.0.2", "X-Forwarded-For: 10.0.0.3\r\n") ==
        std::pair{200, std::string()});
  CHECK(new_session_from(port, "127.0.0.2", "X-Forwarded-For: 10.0.0.4\r\n") ==
        std::pair{200, std::string()});
  CHECK(new_session_from(port, "127.0.0.2", "X-Forwarded-For: 10.0.0.5\r\n") ==
        std::pair{429, std::string("too_many_sessions")});
  // A listed proxy that forwards no address is refused, not counted as itself.
  CHECK(new_session_from(port, "127.0.0.1", "X-Forwarded-For: unknown\r\n") ==
        std::pair{400, std::string("bad_forwarded_for")});
}

TEST_CASE("X-Forwarded-Proto: https from a listed proxy makes cookies Secure, from others not",
          "[tls][proxy]") {
  StudioServer server(fresh_dir("proxy-proto"), {"serve.behind_proxy=[127.0.0.1]"});
  server.add_account("ana", "ana's password");
  const std::string https = "X-Forwarded-Proto: https\r\nX-Forwarded-For: 10.0.0.1\r\n";
  const RawAnswer proxied = raw_post(server.port(), "127.0.0.1", "/api/v1/login", kAna, https);
  CHECK(proxied.status == 200);
  const std::string token = proxied.set_cookie.substr(0, proxied.set_cookie.find(';'));
  CHECK(proxied.set_cookie == token + kCookieTail + "; Secure");
  const RawAnswer direct = raw_post(server.port(), "127.0.0.2", "/api/v1/login", kAna, https);
  CHECK(direct.status == 200);
  const std::string direct_token = direct.set_cookie.substr(0, direct.set_cookie.find(';'));
  CHECK(direct.set_cookie == direct_token + kCookieTail);
  // Behind a TLS proxy the browser's Origin is https://; from a peer that is no proxy it is not
  // this page's origin.
  const std::string origin = "Origin: https://127.0.0.1:" + std::to_string(server.port()) + "\r\n";
  CHECK(raw_post(server.port(), "127.0.0.1", "/api/v1/logout", "", https + origin).status == 200);
  CHECK(raw_post(server.port(), "127.0.0.2", "/api/v1/logout", "", https + origin).status == 403);
}

TEST_CASE("a Host without a port means 443 on a page a listed proxy says is HTTPS",
          "[tls][proxy]") {
  StudioServer server(fresh_dir("proxy-host"), {"serve.behind_proxy=[127.0.0.1]",
                                                "serve.allowed_hosts=[study.example:443]"});
  const auto status = [&](const std::string& source, const std::string& headers) {
    return raw_post(server.port(), source, "/api/v1/request", R"({"op":"state"})", headers,
                    "study.example")
        .status;
  };
  CHECK(status("127.0.0.1", "X-Forwarded-Proto: https\r\n") == 200);
  CHECK(status("127.0.0.1", "X-Forwarded-Proto: http\r\n") == 421);
  CHECK(status("127.0.0.1", "") == 421);
  CHECK(status("127.0.0.2", "X-Forwarded-Proto: https\r\n") == 421);
}

TEST_CASE("a listed proxy's connections are not capped per address", "[tls][proxy]") {
  StudioServer server(fresh_dir("proxy-conns"),
                      {"serve.behind_proxy=[127.0.0.1]", "serve.max_connections_per_address=1"});
  RawSocket first(server.port(), "127.0.0.1");
  RawSocket second(server.port(), "127.0.0.1");
  REQUIRE(first.connected());
  REQUIRE(second.connected());
  CHECK(new_session_from(server.port(), "127.0.0.1", "X-Forwarded-For: 10.0.0.1\r\n") ==
        std::pair{200, std::string()});
  // Another peer is capped as before: its second connection is refused.
  RawSocket other(server.port(), "127.0.0.2");
  REQUIRE(other.connected());
  RawSocket over(server.port(), "127.0.0.2");
  bool closed = false;
  CHECK_THAT(over.read_all(10s, &closed),
             Catch::StartsWith("HTTP/1.1 503") && Catch::Contains("too_many_connections"));
  CHECK(closed);
}

}  // namespace flipper::studiotest
