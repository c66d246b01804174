// What every answer of `flipper serve` tells a browser, and what its messages do not tell a
// client (docs/studio.md §2 "Headers" and "Messages"): no framing by another site, no type
// sniffing, no referrer, a CSP on the page and on API answers alike; no absolute server path in
// any message.
#include <chrono>

#include "http_types.hpp"
#include "raw_socket.hpp"
#include "studio_server.hpp"

namespace flipper::studiotest {
namespace {

void check_security_headers(const httplib::Result& res, const std::string& what) {
  INFO(what);
  REQUIRE(res);
  CHECK(res->get_header_value("X-Content-Type-Options") == "nosniff");
  CHECK(res->get_header_value("X-Frame-Options") == "DENY");
  CHECK(res->get_header_value("Referrer-Policy") == "no-referrer");
  CHECK_THAT(res->get_header_value("Content-Security-Policy"),
             Catch::Contains("frame-ancestors 'none'"));
}

TEST_CASE("every answer forbids framing and sniffing and sends no referrer") {
  StudioServer server(fresh_dir("headers"));
  auto http = server.client();
  auto page = http.Get("/");
  check_security_headers(page, "the page");
  CHECK_THAT(page->get_header_value("Content-Security-Policy"),
             Catch::StartsWith("default-src 'self'"));
  check_security_headers(http.Get("/app.js"), "a script");
  auto api = http.Post("/api/v1/request", R"({"op":"state"})", "application/json");
  check_security_headers(api, "an API answer");
  CHECK(api->get_header_value("Content-Security-Policy") ==
        "default-src 'none'; frame-ancestors 'none'");
  check_security_headers(http.Get("/api/v1/info"), "info");
  check_security_headers(http.Get("/no-such-page"), "a 404");
  check_security_headers(http.Post("/api/v1/request", "not json", "application/json"), "a 400");
  httplib::Headers wrong_host{{"Host", "evil.example:" + std::to_string(server.port())}};
  check_security_headers(http.Get("/", wrong_host), "a 421");
}

TEST_CASE("a connection over the cap is refused with the same headers") {
  StudioServer server(fresh_dir("headers-cap"), {"serve.max_connections_per_address=1"});
  RawSocket first(server.port());
  REQUIRE(first.connected());
  RawSocket second(server.port());
  REQUIRE(second.connected());
  bool closed = false;
  const std::string text = second.read_all(std::chrono::seconds(10), &closed);
  CHECK(closed);
  CHECK_THAT(text, Catch::StartsWith("HTTP/1.1 503") && Catch::Contains("too_many_connections") &&
                       Catch::Contains("\r\nX-Frame-Options: DENY\r\n") &&
                       Catch::Contains("\r\nX-Content-Type-Options: nosniff\r\n"));
}

TEST_CASE("without_paths cuts absolute paths to their last part and leaves the rest") {
  using studio::without_paths;
  CHECK(without_paths("cannot write '/srv/study/rec/queries.jsonl': No space left on device") ==
        "cannot write 'queries.jsonl': No space left on device");
  CHECK(without_paths("/a/b at the start, (/c/d) inside, \"/e\" quoted") ==
        "b at the start, (d) inside, \"e\" quoted");
  CHECK(without_paths("a folder /srv/x/ and the root / alone") ==
        "a folder … and the root / alone");
  CHECK(without_paths("relative 'worlds/a.json', 3/4, and/or") ==
        "relative 'worlds/a.json', 3/4, and/or");
}

TEST_CASE("messages to clients name no server path") {
  StudioServer server(fresh_dir("paths"));
  auto http = server.client();
  const std::string s = new_session(http);
  const std::string source = FLIPPER_SOURCE_DIR;
  // A world file that is missing, one outside the world folder, one that is not a world.
  for (const char* file : {"nope.json", "../../../../etc/passwd", "../default.yaml"}) {
    INFO(file);
    const Reply r = post_json(http, s, json{{"op", "world"}, {"file", file}});
    CHECK(r.body["ok"] == false);
    const std::string message = r.body["error"]["message"];
    CHECK_FALSE(message.empty());
    CHECK(message.find(source) == std::string::npos);
    CHECK(message.find("/configs/") == std::string::npos);
  }
  const Reply missing = post_json(http, s, json{{"op", "world"}, {"file", "nope.json"}});
  CHECK_THAT(std::string(missing.body["error"]["message"]), Catch::Contains("nope.json"));
}

}  // namespace
}  // namespace flipper::studiotest
