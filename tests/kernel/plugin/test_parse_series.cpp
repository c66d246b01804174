// Several parses as one series (kernel::checked_parses, docs/plugins-untrusted.md §6): one child
// process for all of them when the parser is isolated, the outcomes read as if each parse were
// made after the ones before it: the series ends at the first failure (an exception, a crash, an
// answer that breaks the contract), the parses before it keep their results, none after it is
// made. Which process made a parse is the oracle: the scripted parser writes its pid into the
// result's `derivations` (a statistic the wire carries as it is).
#include <unistd.h>

#include <catch2/catch.hpp>
#include <csignal>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "flipper/kernel/isolation.hpp"
#include "flipper/kernel/plugin_checks.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/testing/core_scorer.hpp"

using namespace flipper;

namespace {

// Parses "move <word>" into one core candidate {move <word>}, its `derivations` the pid of the
// process that parsed it; `fail_on` names a word whose parse does what `failure` does.
class SeriesParser : public sdk::Parser {
 public:
  std::string fail_on;
  std::function<void()> failure;
  mutable int made = 0;  // parses made in this process (in a child: dies with it)

 protected:
  void do_set_grammar(std::shared_ptr<const sdk::Grammar>) override {}
  void do_add_rule(sdk::RulePtr) override {}
  void do_remove_rule(const std::string&) override {}
  sdk::ParseResult do_parse(const sdk::ParseRequest& r) const override {
    ++made;
    if (r.tokens.size() > 1 && r.tokens[1] == fail_on) failure();
    sdk::ParseResult out;
    out.derivations = static_cast<std::uint64_t>(::getpid());
    if (r.tokens.size() != 2 || r.tokens[0] != "move") return out;
    sdk::Candidate c;
    c.program = sdk::make(sdk::Kind::Move, {sdk::make_word(sdk::Kind::Direction, r.tokens[1])});
    c.score = r.tokens[1] == "nan" ? std::numeric_limits<double>::quiet_NaN() : 1.0;
    c.core_only = true;
    out.candidates.push_back(std::move(c));
    return out;
  }
};

struct Series {
  std::shared_ptr<SeriesParser> parser = std::make_shared<SeriesParser>();
  testing::CoreScorer scorer;  // the parser never calls it
  sdk::StopCondition stop;

  kernel::PluginRef<const sdk::Parser> ref(kernel::Isolation isolation) const {
    return kernel::PluginRef<const sdk::Parser>(
               std::static_pointer_cast<const sdk::Parser>(parser),
               kernel::PluginId{"parser", "series", "/p/libseries.so"})
        .with_isolation(isolation);
  }
  std::vector<sdk::ParseRequest> requests(const std::vector<std::string>& words) const {
    std::vector<sdk::ParseRequest> out;
    for (const auto& w : words) {
      sdk::ParseRequest r;
      r.tokens = {"move", w};
      r.scorer = &scorer;
      r.stop = stop;
      out.push_back(std::move(r));
    }
    return out;
  }
};

// "CODE: MESSAGE" of an outcome's error.
std::string error_of(const std::exception_ptr& e) {
  if (!e) return "(none)";
  try {
    std::rethrow_exception(e);
  } catch (const sdk::Error& x) {
    return x.code() + ": " + x.what();
  } catch (...) {
  }
  return "(other)";
}

std::string program_of(const kernel::ParseOutcome& o) {
  return o.result.candidates.empty() ? "(none)" : sdk::render(o.result.candidates[0].program);
}

}  // namespace

TEST_CASE("an isolated series is made in one child, with the results of parses made one by one",
          "[isolation][parser][series]") {
  Series s;
  const auto words = std::vector<std::string>{"left", "right", "forward"};
  const auto isolated =
      kernel::checked_parses(s.ref(kernel::Isolation::process), s.requests(words), s.stop);
  REQUIRE(isolated.size() == 3u);
  const auto child = isolated[0].result.derivations;
  CHECK(child != static_cast<std::uint64_t>(::getpid()));
  for (std::size_t i = 0; i < 3; ++i) {
    CHECK_FALSE(isolated[i].error);
    CHECK(isolated[i].result.derivations == child);  // one process made all three
    CHECK(program_of(isolated[i]) == "{move " + words[i] + "}");
  }
  CHECK(s.parser->made == 0);  // none in this process

  const auto in_process =
      kernel::checked_parses(s.ref(kernel::Isolation::in_process), s.requests(words), s.stop);
  REQUIRE(in_process.size() == 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    CHECK(in_process[i].result.derivations == static_cast<std::uint64_t>(::getpid()));
    CHECK(program_of(in_process[i]) == program_of(isolated[i]));
  }
  CHECK(s.parser->made == 3);

  // One request is one checked_parse, in a child of its own.
  const auto one =
      kernel::checked_parses(s.ref(kernel::Isolation::process), s.requests({"left"}), s.stop);
  REQUIRE(one.size() == 1u);
  CHECK(one[0].result.derivations != child);
  CHECK(one[0].result.derivations != static_cast<std::uint64_t>(::getpid()));
  CHECK(kernel::checked_parses(s.ref(kernel::Isolation::process), {}, s.stop).empty());
}

TEST_CASE("a series ends at its first failure, the parses before it keeping their results",
          "[isolation][parser][series]") {
  const std::vector<std::string> words{"left", "right", "back", "forward"};
  using Expected = std::string;
  struct Case {
    const char* what;
    std::function<void()> failure;
    Expected isolated, in_process;
  };
  const Expected thrown = "no_parse: the parser gave up on 'back'";
  const std::vector<Case> cases{
      {"a crash (SIGSEGV)", [] { std::raise(SIGSEGV); },
       "plugin_crashed: plugin 'series' (/p/libseries.so): parse: SIGSEGV", "(not in process)"},
      {"an abort", [] { std::abort(); },
       "plugin_crashed: plugin 'series' (/p/libseries.so): parse: SIGABRT", "(not in process)"},
      {"an sdk::Error", [] { throw sdk::Error("no_parse", "the parser gave up on 'back'"); },
       thrown, thrown},
      {"another exception", [] { throw std::runtime_error("oops"); },
       "plugin_error: plugin 'series' (/p/libseries.so): parse: oops",
       "plugin_error: plugin 'series' (/p/libseries.so): parse: oops"},
  };
  for (const auto& c : cases) {
    SECTION(c.what) {
      for (const bool isolate : {true, false}) {
        if (!isolate && c.in_process == "(not in process)") continue;
        Series s;
        s.parser->fail_on = "back";
        s.parser->failure = c.failure;
        const auto out = kernel::checked_parses(
            s.ref(isolate ? kernel::Isolation::process : kernel::Isolation::in_process),
            s.requests(words), s.stop);
        INFO((isolate ? "isolated" : "in process"));
        REQUIRE(out.size() == 3u);  // "forward", after the failure, is not parsed
        CHECK(program_of(out[0]) == "{move left}");
        CHECK(program_of(out[1]) == "{move right}");
        CHECK_FALSE(out[0].error);
        CHECK_FALSE(out[1].error);
        CHECK(error_of(out[2].error) == (isolate ? c.isolated : c.in_process));
        if (isolate) CHECK(out[0].result.derivations == out[1].result.derivations);
        CHECK(s.parser->made == (isolate ? 0 : 3));
      }
    }
  }
}

TEST_CASE("a series' first parse crashing, and an answer breaking the contract, end it there",
          "[isolation][parser][series]") {
  for (const bool isolate : {true, false}) {
    INFO((isolate ? "isolated" : "in process"));
    const auto isolation = isolate ? kernel::Isolation::process : kernel::Isolation::in_process;
    Series s;
    // The contract is checked in the parent, per parse, in order: a NaN score is the second's.
    const auto out =
        kernel::checked_parses(s.ref(isolation), s.requests({"left", "nan", "right"}), s.stop);
    REQUIRE(out.size() == 2u);
    CHECK(program_of(out[0]) == "{move left}");
    CHECK(error_of(out[1].error) ==
          "invalid_score: plugin 'series' (/p/libseries.so): candidate 0 has the score nan");
    if (!isolate) continue;
    s.parser->fail_on = "left";
    s.parser->failure = [] { std::raise(SIGKILL); };
    const auto first =
        kernel::checked_parses(s.ref(isolation), s.requests({"left", "right"}), s.stop);
    REQUIRE(first.size() == 1u);
    CHECK(error_of(first[0].error) ==
          "plugin_crashed: plugin 'series' (/p/libseries.so): parse: SIGKILL");
  }
}

TEST_CASE("send_part outside an isolated call's child is refused", "[isolation][series]") {
  CHECK_THROWS_AS(kernel::detail::send_part("x"), std::logic_error);
}
