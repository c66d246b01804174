// The session's one extension interface (docs/architecture.md §3 "Session extensions"): ops and
// typed events, attached again by the session itself on rebind.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "flipper/kernel/session_extension.hpp"
#include "flipper/naturalization/naturalize_ops.hpp"
#include "flipper/sdk/errors.hpp"
#include "session_fixture.hpp"

using flipper::kernel::Json;
using flipper::kernel::Session;
using flipper::testsupport::ask;
using flipper::testsupport::error_code;
using flipper::toolkit::json::JsonWriter;
namespace k = flipper::kernel;

namespace {

// Records every kernel event it is told, as one line each.
struct Log {
  std::vector<std::string> lines;
  std::shared_ptr<k::SessionExtension> extension(const std::string& tag) {
    return k::make_extension([this, tag](Session& s) {
      lines.push_back(tag + " attached");
      s.on<k::QueryBegins>(
          [this, tag](const k::QueryBegins& e) { lines.push_back(tag + " query " + e.text); });
      s.on<k::QueryAnswered>([this, tag](const k::QueryAnswered& e) {
        lines.push_back(tag + " answered " + std::to_string(e.result.query->shown.size()));
      });
      s.on<k::UserChanged>(
          [this, tag](const k::UserChanged& e) { lines.push_back(tag + " user " + e.user); });
      s.on<k::Accepting>([this, tag](const k::Accepting& e) {
        lines.push_back(tag + " accepting " + std::to_string(e.rank) + " " + e.user);
      });
      s.on<k::PlanAccepted>([this, tag](const k::PlanAccepted& e) {
        lines.push_back(tag + " plan " + std::to_string(e.sequence) + " " + e.formula);
      });
      s.on<k::Activated>([this, tag](const k::Activated& e) {
        lines.push_back(tag + " activated " + e.session.user());
      });
    });
  }
};

std::vector<std::string> tail(const std::vector<std::string>& v, std::size_t from) {
  return {v.begin() + static_cast<std::ptrdiff_t>(from), v.end()};
}

}  // namespace

TEST_CASE("extensions are told the kernel's events with their payloads, in install order",
          "[session][extensions]") {
  auto s = flipper::testsupport::bare_session();
  Log log;
  s->install(log.extension("a"));
  s->install(log.extension("b"));
  CHECK(log.lines == std::vector<std::string>{"a attached", "b attached"});
  REQUIRE(ask(*s, R"({"op":"user","name":"ana"})")["ok"] == true);
  REQUIRE(ask(*s, R"({"op":"query","text":"move up","k":2})")["ok"] == true);
  REQUIRE(ask(*s, R"({"op":"accept","rank":0})")["ok"] == true);
  s->activate();
  CHECK(tail(log.lines, 2) ==
        std::vector<std::string>{"a user ana", "b user ana", "a query move up", "b query move up",
                                 "a answered 1", "b answered 1", "a accepting 0 ana",
                                 "b accepting 0 ana", "a plan 1 {move up}", "b plan 1 {move up}",
                                 "a activated ana", "b activated ana"});
}

TEST_CASE("rebind attaches the runtime's extensions and the session's own again, in order",
          "[session][extensions]") {
  Log log;
  const auto runtime_a = flipper::testsupport::test_runtime();
  const auto runtime_b = flipper::testsupport::test_runtime();
  Session s(runtime_a, {log.extension("ra")});
  s.install(log.extension("own"));
  s.install(k::make_extension([](Session& session) {
    session.set_op("echo",
                   [](Session&, const Json& r, JsonWriter& a) { a.key("t").value(r["t"]); });
  }));
  REQUIRE(ask(s, R"({"op":"echo","t":1})")["t"] == 1);
  CHECK(log.lines == std::vector<std::string>{"ra attached", "own attached"});

  s.rebind(runtime_b, {log.extension("rb")});
  CHECK(&s.runtime() == runtime_b.get());
  // ra is gone (it belonged to runtime a); the session's own come after rb, once each.
  CHECK(tail(log.lines, 2) == std::vector<std::string>{"rb attached", "own attached"});
  REQUIRE(ask(s, R"({"op":"echo","t":2})")["t"] == 2);
  REQUIRE(ask(s, R"({"op":"query","text":"move up"})")["ok"] == true);
  CHECK(tail(log.lines, 4) == std::vector<std::string>{"rb query move up", "own query move up",
                                                       "rb answered 1", "own answered 1"});
  // A second rebind does not attach anything twice.
  s.rebind(runtime_a, {});
  CHECK(tail(log.lines, 8) == std::vector<std::string>{"own attached"});
  REQUIRE(ask(s, R"({"op":"query","text":"move up"})")["ok"] == true);
  CHECK(tail(log.lines, 9) == std::vector<std::string>{"own query move up", "own answered 1"});
}

TEST_CASE(
    "an Accepting subscriber that throws undoes the accept, PlanAccepted failures are "
    "contained",
    "[session][extensions]") {
  auto s = flipper::testsupport::bare_session();
  bool refuse = true;
  int plans = 0;
  s->install(k::make_extension([&](Session& session) {
    session.on<k::Accepting>([&](const k::Accepting&) {
      if (refuse) throw flipper::sdk::Error("lexicon_busy", "the store is busy");
    });
    session.on<k::PlanAccepted>(
        [](const k::PlanAccepted&) { throw std::runtime_error("robot unreachable"); });
    session.on<k::PlanAccepted>(
        [&](const k::PlanAccepted& e) { plans = static_cast<int>(e.sequence); });
  }));
  const Json before = ask(*s, R"({"op":"state"})")["world"];
  REQUIRE(ask(*s, R"({"op":"query","text":"move up"})")["ok"] == true);
  const Json refused = ask(*s, R"({"op":"accept","rank":0})");
  CHECK(error_code(refused) == "lexicon_busy");
  CHECK(ask(*s, R"({"op":"state"})")["world"] == before);
  CHECK(plans == 0);
  refuse = false;
  const Json accepted = ask(*s, R"({"op":"accept","rank":0})");  // the query is still pending
  CHECK(accepted["ok"] == true);
  CHECK(plans == 1);  // told although the subscriber before it threw
  CHECK(ask(*s, R"({"op":"state"})")["world"] != before);
}

TEST_CASE("RequestAnswered tells each op's refusal code, RulesDefined what a define stored",
          "[session][extensions]") {
  auto s = flipper::wiring::open_session(std::nullopt, flipper::testsupport::test_overrides());
  std::vector<std::string> heard;
  s->install(k::make_extension([&heard](Session& session) {
    session.on<k::RequestAnswered>([&heard](const k::RequestAnswered& e) {
      heard.push_back(e.op + ":" + (e.code.empty() ? "ok" : e.code));
    });
    session.on<flipper::naturalization::RulesDefined>(
        [&heard](const flipper::naturalization::RulesDefined& e) {
          std::string ids;
          for (const auto& r : e.outcome.rules) ids += r->id + " ";
          heard.push_back("defined " + e.call.head + ": " + ids);
        });
  }));
  CHECK(error_code(ask(*s, R"({"op":"accept","rank":0})")) == "no_query");
  CHECK(error_code(ask(*s, R"({"op":"nope"})")) == "unknown_op");  // no op ran: not told
  const Json defined =
      ask(*s, R"({"op":"define","head":"go twice up","body":["move up","move up"]})");
  REQUIRE(defined["ok"] == true);
  std::string ids;
  for (const auto& r : defined["rules"]) ids += r["id"].get<std::string>() + " ";
  REQUIRE_FALSE(ids.empty());
  CHECK(heard ==
        std::vector<std::string>{"accept:no_query", "defined go twice up: " + ids, "define:ok"});
}
