// plugins.isolation: process for a scorer's learn (docs/plugins-untrusted.md §6): an accept whose
// learn segfaults, aborts or throws costs the one answer. In `flipper serve` (isolation `auto` is
// `process` there) user A's accept is answered plugin_crashed naming plugin, call and signal, the
// model is unchanged (user B's answers before and after are exactly a fresh in-process session's),
// and A's next query and accept are answered. The evil scorer (tests/support/evil_scorer)
// misbehaves only on accepts of utterances with the token `room1` (`on_token=room1`).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "apps/studio/studio_server.hpp"
#include "cli_test_support.hpp"
#include "isolation_test_support.hpp"

using namespace flipper;
using nlohmann::json;
using namespace flipper::isolationtest;

namespace {

// Servers name a plugin's library by its file name only (no paths to a remote client).
const std::string kServeLabel = "plugin 'evil_scorer' (evil_scorer.so)";
const std::string kCrashing = R"({"op":"query","text":"visit room1"})";
const std::string kFine = R"({"op":"query","text":"visit room4 and room2","k":3})";
const std::string kAccept = R"({"op":"accept","rank":0})";

std::vector<std::string> evil_sets(const std::string& mode) {
  return {"plugin_paths=[" + kEvilDir + "]", "scorer.plugin=evil_scorer",
          "scorer.params.mode=" + mode, "scorer.params.on_token=room1"};
}

// The answers of a fresh `flipper session`, the evil scorer in mode ok, in process, to `lines`.
std::vector<json> reference(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  const std::string in = clitest::write_own_file("scorer-isolation-reference.jsonl", text);
  const auto r = clitest::run_flipper(
      "session --set lexicon.path=:memory: --set lexicon.preload=" + set_args(evil_sets("ok")) +
          " --set plugins.isolation=in_process " + in,
      false);
  REQUIRE(r.status == 0);
  std::vector<json> out;
  std::size_t from = 0;
  for (std::size_t at = r.out.find('\n'); at != std::string::npos; at = r.out.find('\n', from)) {
    out.push_back(without_ms(json::parse(r.out.substr(from, at - from))));
    from = at + 1;
  }
  REQUIRE(out.size() == lines.size());
  return out;
}

// Two users of one server: B queries, A accepts a query whose learn misbehaves, B queries again,
// A queries and accepts again.
void bad_learn_costs_one_answer(const std::string& mode, const json& expected) {
  studiotest::StudioServer server(studiotest::fresh_dir("scorer-isolation"),
                                  isolated_server(evil_sets(mode)));
  const auto fine = reference({kFine, kAccept, kFine});
  // The accept taught the model: the same query scores higher after it.
  REQUIRE(fine[0]["candidates"][0]["score"] == 7.0);
  REQUIRE(fine[2]["candidates"][0]["score"] == 47.5);
  auto http_a = server.client();
  auto http_b = server.client();
  const auto a = studiotest::post(http_a, "", R"({"op":"state"})");
  const auto b = studiotest::post(http_b, "", R"({"op":"state"})");
  REQUIRE(a.status == 200);
  REQUIRE(b.status == 200);
  REQUIRE(a.session != b.session);
  CHECK(without_ms(studiotest::post(http_b, b.session, kFine).body) == fine[0]);
  REQUIRE(studiotest::post(http_a, a.session, kCrashing).body["ok"] == true);
  const auto bad = studiotest::post(http_a, a.session, kAccept);
  CHECK(bad.body == expected);
  CHECK(without_ms(studiotest::post(http_b, b.session, kFine).body) == fine[0]);
  CHECK(without_ms(studiotest::post(http_a, a.session, kFine).body) == fine[0]);
  CHECK(without_ms(studiotest::post(http_a, a.session, kAccept).body) == fine[1]);
  CHECK(without_ms(studiotest::post(http_a, a.session, kFine).body) == fine[2]);
  CHECK(server.stop() == 0);
}

json accept_error(const std::string& code, const std::string& message) {
  return json{{"ok", false},
              {"op", "accept"},
              {"error", {{"code", code}, {"message", kServeLabel + ": " + message}}}};
}

}  // namespace

TEST_CASE("serve: a scorer whose learn segfaults costs user A one answer, user B nothing",
          "[isolation][scorer]") {
  bad_learn_costs_one_answer("segv", accept_error("plugin_crashed", "learn: SIGSEGV"));
}

TEST_CASE("serve: a scorer whose learn aborts costs user A one answer, user B nothing",
          "[isolation][scorer]") {
  bad_learn_costs_one_answer("abort", accept_error("plugin_crashed", "learn: SIGABRT"));
}

TEST_CASE("serve: an isolated learn's exception arrives as in process (plugin_error)",
          "[isolation][scorer]") {
  bad_learn_costs_one_answer("throw",
                             accept_error("plugin_error", "learn: evil_scorer: thrown on purpose"));
}

TEST_CASE(
    "a scorer whose reported changes do not add up to its weights: the kernel holds the stored "
    "sums, so the next start ranks exactly as the session did",
    "[isolation][scorer][stored_sums]") {
  // The stored sums are the truth every kernel over a lexicon reads (docs/naturalization.md §5
  // "Learned state"): after each accept the kernel takes them back into the scorer, whatever the
  // scorer holds. The evil scorer learns as in mode ok but reports each change rounded to a
  // float. Oracles: a second session over the same store (what it loads is the stored sums), and
  // mode ok in process (the weights the scorer really learnt, which the session must not keep).
  const std::string store = clitest::scratch("stored-sums.sqlite");
  const std::vector<std::string> taught = {kFine, kAccept, kFine, kAccept, kFine, kAccept, kFine};
  const auto run = [&](const std::vector<std::string>& lines) {
    std::string text;
    for (const auto& l : lines) text += l + "\n";
    const std::string in = clitest::write_file("stored-sums.jsonl", text);
    const auto r =
        clitest::run_flipper("session --set lexicon.path=" + store +
                                 " --set lexicon.preload=" + set_args(evil_sets("inexact")) +
                                 " --set plugins.isolation=in_process " + in,
                             false);
    REQUIRE(r.status == 0);
    const auto last = r.out.rfind('\n', r.out.size() - 2);
    return without_ms(json::parse(r.out.substr(last == std::string::npos ? 0 : last + 1)));
  };
  const json session = run(taught);
  const json restarted = run({kFine});
  const json learnt = reference(taught).back();
  REQUIRE(session["ok"] == true);
  CHECK(session == restarted);
  CHECK(session != learnt);  // the rounding is visible in the scores at all
  // Same readings, only the scores differ.
  REQUIRE(session["candidates"].size() == learnt["candidates"].size());
  for (std::size_t i = 0; i < learnt["candidates"].size(); ++i)
    CHECK(session["candidates"][i]["formula"] == learnt["candidates"][i]["formula"]);
}
