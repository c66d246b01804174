// plugins.isolation: process for a parser (docs/plugins-untrusted.md §6): a parse that segfaults
// or aborts costs the one answer it was computing. In `flipper serve` (isolation `auto` is
// `process` there) user A's query is answered plugin_crashed naming plugin, call and signal, the
// server stays up, user B's session answers exactly as a fresh in-process session does, and A's
// next query is answered. The evil parser (tests/support/evil_parser) misbehaves only on
// utterances with the token `room1` (`on_token=room1`) and parses as `chart` otherwise.
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

const std::string kLabel = "plugin 'evil_parser' (" + kEvilDir + "/evil_parser.so)";
// Servers name a plugin's library by its file name only (no paths to a remote client).
const std::string kServeLabel = "plugin 'evil_parser' (evil_parser.so)";
const std::string kCrashing = R"({"op":"query","text":"visit room1"})";
const std::string kFine = R"({"op":"query","text":"visit room4"})";

std::vector<std::string> evil_sets(const std::string& mode) {
  return {"plugin_paths=[" + kEvilDir + "]", "parser.plugin=evil_parser",
          "parser.params.mode=" + mode, "parser.params.on_token=room1"};
}

// The answer to kFine of a fresh `flipper session` with the evil parser in mode ok, in process:
// the reference for user B's answers and A's next one.
json reference() {
  const std::string in = clitest::write_own_file("parser-isolation-reference.jsonl", kFine + "\n");
  const auto r = clitest::run_flipper(
      "session --set lexicon.path=:memory: --set lexicon.preload=" + set_args(evil_sets("ok")) +
          " --set plugins.isolation=in_process " + in,
      false);
  REQUIRE(r.status == 0);
  return without_ms(json::parse(r.out));
}

json query_error(const std::string& code, const std::string& message) {
  return json{{"ok", false},
              {"op", "query"},
              {"error", {{"code", code}, {"message", kServeLabel + ": " + message}}}};
}

// Two users of one server: B answered, A's query whose parse misbehaves, B again, A again.
void bad_parse_costs_one_answer(const std::string& mode, const json& expected) {
  studiotest::StudioServer server(studiotest::fresh_dir("parser-isolation"),
                                  isolated_server(evil_sets(mode)));
  const json fine = reference();
  REQUIRE(fine["candidates"].size() == 1u);
  CHECK(fine["candidates"][0]["formula"] == "{visit room4}");
  auto http_a = server.client();
  auto http_b = server.client();
  const auto a = studiotest::post(http_a, "", R"({"op":"state"})");
  const auto b = studiotest::post(http_b, "", R"({"op":"state"})");
  REQUIRE(a.status == 200);
  REQUIRE(b.status == 200);
  REQUIRE(a.session != b.session);
  CHECK(without_ms(studiotest::post(http_b, b.session, kFine).body) == fine);
  const auto bad = studiotest::post(http_a, a.session, kCrashing);
  CHECK(bad.body == expected);
  CHECK(without_ms(studiotest::post(http_b, b.session, kFine).body) == fine);
  CHECK(without_ms(studiotest::post(http_a, a.session, kFine).body) == fine);
  CHECK(server.stop() == 0);
}

}  // namespace

TEST_CASE("serve: a parser that segfaults costs user A one answer, user B nothing",
          "[isolation][parser]") {
  bad_parse_costs_one_answer("segv", query_error("plugin_crashed", "parse: SIGSEGV"));
}

TEST_CASE("serve: a parser that aborts costs user A one answer, user B nothing",
          "[isolation][parser]") {
  bad_parse_costs_one_answer("abort", query_error("plugin_crashed", "parse: SIGABRT"));
}

TEST_CASE("serve: an isolated parser's span outside the utterance is refused after the pipe",
          "[isolation][parser]") {
  bad_parse_costs_one_answer(
      "span", query_error("invalid_candidate",
                          "candidate 0 has a derivation over tokens [0, 3), not the whole "
                          "utterance [0, 2)"));
}

TEST_CASE("serve: an isolated parser's exception arrives as in process (plugin_error)",
          "[isolation][parser]") {
  bad_parse_costs_one_answer("throw",
                             query_error("plugin_error", "parse: evil_parser: thrown on purpose"));
}

TEST_CASE("run: a parser's misbehaviour, isolated and in process", "[isolation][parser]") {
  // Each mode in a child process, then in process (`auto` is in_process outside the servers):
  // the same refusal, except that a crash ends the in-process run as it always did.
  struct Case {
    std::string mode, isolated, in_process;
    int in_process_status;
  };
  const std::string prefix = "flipper run: ";
  const std::vector<Case> cases = {
      {"segv", "[plugin_crashed] " + kLabel + ": parse: SIGSEGV", "", 128 + 11},
      {"abort", "[plugin_crashed] " + kLabel + ": parse: SIGABRT", "", 128 + 6},
      {"throw", "[plugin_error] " + kLabel + ": parse: evil_parser: thrown on purpose", "same", 1},
      {"span",
       "[invalid_candidate] " + kLabel +
           ": candidate 0 has a derivation over tokens [0, 3), not the whole utterance [0, 2)",
       "same", 1},
      {"nan", "[invalid_score] " + kLabel + ": candidate 0 has the score nan", "same", 1},
  };
  for (const Case& c : cases) {
    INFO("mode " << c.mode);
    const std::string sets = set_args(evil_sets(c.mode));
    const auto isolated =
        clitest::run_flipper("run" + sets + " --set plugins.isolation=process \"visit room1\"");
    CHECK(isolated.status == 1);
    CHECK(isolated.out == prefix + c.isolated + "\n");
    // ASan would catch the SIGSEGV and exit 1 unless told not to (the instrumented build).
    const auto in_process = clitest::run_shell("ASAN_OPTIONS=handle_segv=0:handle_abort=0 " +
                                               std::string(FLIPPER_BINARY_DIR) +
                                               "/bin/flipper run" + sets + " \"visit room1\" 2>&1");
    CHECK(in_process.status == c.in_process_status);
    if (c.in_process == "same") CHECK(in_process.out == prefix + c.isolated + "\n");
    const auto fine =
        clitest::run_flipper("run" + sets + " --set plugins.isolation=process \"visit room4\"");
    CHECK(fine.status == 0);
  }
}

TEST_CASE("session: a definition's parses are one series, read in order, isolated or not",
          "[isolation][parser][series]") {
  // The head and the body lines are parsed in one child (kernel::checked_parses) and read in
  // order: a body line whose parse crashes is the definition's plugin_crashed, yet a head that
  // is core is refused first (its parse comes before the body's, as one call after another
  // would have it), and the session answers the next definition.
  const std::string in =
      clitest::write_file("parser-isolation-define.jsonl",
                          R"({"op":"define","head":"zq hop","body":["move left","visit room1"]})"
                          "\n"
                          R"({"op":"define","head":"move left","body":["visit room1"]})"
                          "\n"
                          R"({"op":"define","head":"zq room1","body":["move left"]})"
                          "\n"
                          R"({"op":"define","head":"zq hop","body":["move left","move right"]})"
                          "\n");
  struct Case {
    std::string mode, isolation, body_error, head_error;
  };
  const std::string head_is_core = R"({"code":"head_is_core","message":"'move left' already )"
                                   R"(means {move left} in the core language; use it as it is"})";
  const std::vector<Case> cases = {
      {"segv", "process",
       R"({"code":"plugin_crashed","message":")" + kLabel + R"(: parse: SIGSEGV"})",
       R"({"code":"plugin_crashed","message":")" + kLabel + R"(: parse: SIGSEGV"})"},
      {"throw", "process",
       R"({"code":"plugin_error","message":")" + kLabel +
           R"(: parse: evil_parser: thrown on purpose"})",
       R"({"code":"plugin_error","message":")" + kLabel +
           R"(: parse: evil_parser: thrown on purpose"})"},
      {"throw", "in_process",
       R"({"code":"plugin_error","message":")" + kLabel +
           R"(: parse: evil_parser: thrown on purpose"})",
       R"({"code":"plugin_error","message":")" + kLabel +
           R"(: parse: evil_parser: thrown on purpose"})"},
  };
  for (const Case& c : cases) {
    INFO("mode " << c.mode << ", " << c.isolation);
    const auto r = clitest::run_flipper(
        "session --set lexicon.path=:memory: --set lexicon.preload=" + set_args(evil_sets(c.mode)) +
            " --set plugins.isolation=" + c.isolation + " " + in,
        false);
    REQUIRE(r.status == 0);
    std::vector<json> answers;
    std::size_t at = 0;
    for (std::size_t nl; (nl = r.out.find('\n', at)) != std::string::npos; at = nl + 1)
      answers.push_back(json::parse(r.out.substr(at, nl - at)));
    REQUIRE(answers.size() == 4u);
    CHECK(answers[0]["error"] == json::parse(c.body_error));
    CHECK(answers[1]["error"] == json::parse(head_is_core));
    CHECK(answers[2]["error"] == json::parse(c.head_error));
    CHECK(answers[3]["ok"] == true);
    CHECK(answers[3]["rules"][0]["semantics"] == "{{move left};{move right}}");
  }
}
