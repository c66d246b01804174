// The session's input limits at their boundaries (docs/bad-input.md): a request line of exactly
// input.max_line_bytes bytes and an utterance of exactly input.max_tokens tokens are served, one
// byte or one token more is input_too_long. (The bad-input table's rows are far past the limits,
// so a limit off by one passed them.)
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "flipper/kernel/runtime.hpp"
#include "flipper/kernel/session.hpp"
#include "flipper/sdk/errors.hpp"
#include "product_schema.hpp"

using namespace flipper;
using kernel::Json;

namespace {

std::unique_ptr<kernel::Session> session_with(std::vector<std::string> overrides) {
  overrides.push_back("lexicon.path=:memory:");
  return std::make_unique<kernel::Session>(
      kernel::make_runtime(kernel::Config::load(std::nullopt, overrides)));
}

/// A query request line of exactly `bytes` bytes (its text padded with 'a').
std::string query_line(std::size_t bytes) {
  const std::string head = R"({"op":"query","text":")", tail = R"("})";
  REQUIRE(bytes >= head.size() + tail.size() + 1);
  return head + std::string(bytes - head.size() - tail.size(), 'a') + tail;
}

std::string words(std::size_t n) {
  std::string out;
  for (std::size_t i = 0; i < n; ++i) out += i ? " a" : "a";
  return out;
}

std::string code_of(const Json& answer) {
  return answer.contains("error") ? answer["error"].value("code", std::string()) : "";
}

}  // namespace

TEST_CASE("a request line of input.max_line_bytes is served, one byte more is refused",
          "[kernel][limits]") {
  auto s = session_with({"input.max_line_bytes=64"});
  const std::string at = query_line(64);
  REQUIRE(at.size() == 64);
  const Json served = Json::parse(s->handle_line(at));
  INFO(served.dump());
  CHECK(served["ok"] == true);
  CHECK(served["status"] == "unparsable");

  const Json refused = Json::parse(s->handle_line(query_line(65)));
  CHECK(code_of(refused) == "input_too_long");
  CHECK(refused["error"]["message"] ==
        "the request line has 65 bytes; the limit is input.max_line_bytes = 64");
}

TEST_CASE("an utterance of input.max_tokens tokens is parsed, one token more is refused",
          "[kernel][limits]") {
  auto s = session_with({"input.max_tokens=40"});
  kernel::QueryRequest at;
  at.text = words(40);
  CHECK(std::string(s->query(at).status) == "unparsable");

  kernel::QueryRequest over;
  over.text = words(41);
  try {
    (void)s->query(over);
    FAIL("41 tokens were parsed with input.max_tokens = 40");
  } catch (const sdk::Error& e) {
    CHECK(std::string(e.code()) == "input_too_long");
    CHECK(std::string(e.what()) ==
          "the utterance has 41 tokens; the limit is input.max_tokens = 40");
  }
  // The same through the protocol.
  CHECK(s->handle(Json{{"op", "query"}, {"text", words(40)}})["ok"] == true);
  CHECK(code_of(s->handle(Json{{"op", "query"}, {"text", words(41)}})) == "input_too_long");
}
