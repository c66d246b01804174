// apps/wiring, the one place that decides which extensions a session gets
// (flipper/wiring/session_factory.hpp): a session it opens has naturalization's ops where a bare
// kernel session has none; the sessions of one SessionHost share one lexicon, so a phrase one user
// teaches is read in another session; a bad config is refused before anything is built.
#include <catch2/catch.hpp>
#include <string>

#include "flipper/sdk/errors.hpp"
#include "session_fixture.hpp"

using flipper::testsupport::ask;
using flipper::testsupport::bare_session;
using flipper::testsupport::error_code;
using flipper::testsupport::test_overrides;
using flipper::testsupport::test_runtime;
namespace wiring = flipper::wiring;

namespace {

const std::string kDefine = R"({"op":"define","head":"zig zag","body":["move up","move right"]})";

}  // namespace

TEST_CASE("open_session installs naturalization's ops, which a bare session lacks", "[wiring]") {
  auto bare = bare_session();
  CHECK(error_code(ask(*bare, R"({"op":"rules"})")) == "unknown_op");
  CHECK(error_code(ask(*bare, kDefine)) == "unknown_op");

  auto session = wiring::open_session(std::nullopt, test_overrides());
  REQUIRE(session != nullptr);
  const auto rules = ask(*session, R"({"op":"rules"})");
  INFO(rules.dump());
  CHECK(rules["ok"] == true);
  CHECK(rules["rules"].empty());
  const auto defined = ask(*session, kDefine);
  INFO(defined.dump());
  REQUIRE(defined["ok"] == true);
  CHECK(defined["rules"].size() == 1);
  CHECK(ask(*session, R"({"op":"rules"})")["rules"].size() == 1);

  // Over an existing runtime: the same ops.
  auto over_runtime = wiring::open_session(test_runtime());
  CHECK(ask(*over_runtime, R"({"op":"rules"})")["ok"] == true);
}

TEST_CASE("the sessions of one host share its lexicon", "[wiring]") {
  const auto host = wiring::open_host(std::nullopt, test_overrides());
  auto ana = host.open();
  auto bob = host.open();
  REQUIRE(ask(*ana, R"({"op":"user","name":"ana"})")["ok"] == true);
  REQUIRE(ask(*bob, R"({"op":"user","name":"bob"})")["ok"] == true);
  // Before the definition bob's session does not know the phrase.
  CHECK(ask(*bob, R"({"op":"query","text":"zig zag"})")["status"] != "induced");
  REQUIRE(ask(*ana, kDefine)["ok"] == true);
  // Shared lexicon (lexicon.sharing: shared, the default): bob reads ana's phrase.
  const auto answer = ask(*bob, R"({"op":"query","text":"zig zag"})");
  INFO(answer.dump());
  CHECK(answer["ok"] == true);
  CHECK(answer["status"] == "induced");
}

TEST_CASE("a bad config is refused by open_session and open_host", "[wiring]") {
  const auto code_of = [](auto&& open) {
    try {
      open();
    } catch (const flipper::sdk::Error& e) {
      return e.code();
    }
    return std::string("no error");
  };
  CHECK(code_of([] { wiring::open_session(std::nullopt, test_overrides({"session.k=0"})); }) ==
        "bad_config");
  CHECK(code_of([] { wiring::open_host(std::nullopt, test_overrides({"no_such.key=1"})); }) ==
        "bad_config");
}
