// A parser's parse in a child process (kernel/isolation.hpp, docs/plugins-untrusted.md §6): the
// result crosses the pipe whole (programs, rules, derivations, what they share, every field) and
// is checked after it as in process; a parse, or a scorer call within it, that crashes is
// plugin_crashed naming the parse; bytes that are not a whole answer are refused
// (flipper/sdk/answer_wire.hpp), within a bounded nesting.
#include <catch2/catch.hpp>
#include <csignal>
#include <cstring>
#include <functional>
#include <memory>

#include "flipper/kernel/isolation.hpp"
#include "flipper/kernel/plugin_checks.hpp"
#include "flipper/sdk/answer_wire.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/parser.hpp"

using namespace flipper;

namespace {

class ScriptedParser : public sdk::Parser {
 public:
  std::function<sdk::ParseResult(const sdk::ParseRequest&)> parse_does;

 protected:
  void do_set_grammar(std::shared_ptr<const sdk::Grammar>) override {}
  void do_add_rule(sdk::RulePtr) override {}
  void do_remove_rule(const std::string&) override {}
  sdk::ParseResult do_parse(const sdk::ParseRequest& r) const override { return parse_does(r); }
};

// Scores every node 0.5, or crashes when told to.
class ScriptedScorer : public sdk::Scorer {
 public:
  bool crash = false;

 protected:
  double do_score_node(const sdk::Derivation&, const sdk::ScoreContext&) const override {
    if (crash) std::raise(SIGSEGV);
    return 0.5;
  }
  void do_features(const sdk::Derivation&, const sdk::ScoreContext&,
                   sdk::FeatureVector&) const override {}
  void do_learn(const std::vector<sdk::Candidate>&, std::size_t,
                const sdk::ScoreContext&) override {}
  std::string do_save_state() const override { return {}; }
  void do_load_state(std::string_view) override {}
};

struct Fixture {
  std::shared_ptr<ScriptedParser> parser = std::make_shared<ScriptedParser>();
  kernel::PluginRef<const sdk::Parser> ref =
      kernel::PluginRef<const sdk::Parser>(std::static_pointer_cast<const sdk::Parser>(parser),
                                           kernel::PluginId{"parser", "scripted", "/p/libs.so"})
          .with_isolation(kernel::Isolation::process);
  ScriptedScorer scorer;
  sdk::ParseRequest request;
  Fixture() {
    request.tokens = {"visit", "room1", "twice"};
    request.scorer = &scorer;
  }
};

// "visit room1" twice: an induced rule over a core one; the two candidates share a derivation.
sdk::ParseResult two_candidates(const sdk::ParseRequest& r) {
  auto core = std::make_shared<sdk::Rule>();
  core->id = "core:7";
  core->lhs = "$Action";
  core->rhs = {{sdk::Symbol::Type::token, "visit"}, {sdk::Symbol::Type::category, "$Area"}};
  core->sem = sdk::make(sdk::Kind::VisitArea, {sdk::make_hole(0, sdk::Sort::Area)});
  auto induced = std::make_shared<sdk::Rule>(*core);
  induced->id = "r12";
  induced->induced = true;
  induced->how = sdk::RuleOrigin::alignment;
  induced->author = "ann";
  induced->head = "visit room1 twice";
  induced->body = {"visit room1", "visit room1"};
  induced->created = -3;
  const sdk::Program visit =
      sdk::make(sdk::Kind::VisitArea, {sdk::make_word(sdk::Kind::Room, "room1")});
  auto leaf = std::make_shared<sdk::Derivation>();
  leaf->rule = core;
  leaf->start = 0;
  leaf->end = 2;
  leaf->sem = visit;
  leaf->score = r.scorer->score_node(*leaf, r.context) + 0.1;  // 0.6: the scorer is called
  auto top = std::make_shared<sdk::Derivation>(*leaf);
  top->rule = induced;
  top->end = 3;
  top->kids = {leaf};
  top->sem = sdk::make(sdk::Kind::Repeat, {sdk::make_num(2), visit});
  top->score = -1e300;
  top->core_only = false;
  top->newest_rule = 12;
  sdk::ParseResult out;
  out.candidates.resize(2);
  out.candidates[0].program = top->sem;
  out.candidates[0].derivations = {top};
  out.candidates[0].score = top->score;
  out.candidates[0].core_only = false;
  out.candidates[0].newest_rule = 12;
  out.candidates[1] = out.candidates[0];  // the same derivation object twice
  out.candidates[1].score = 0.25;
  out.chart = {leaf};
  out.derivations = 4242;
  out.stopped = false;
  return out;
}

std::pair<std::string, std::string> error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const sdk::Error& e) {
    return {e.code(), e.what()};
  }
  return {"(none)", ""};
}

}  // namespace

TEST_CASE("an isolated parse gives the in-process result, field by field and shared as it was",
          "[isolation][parser]") {
  Fixture f;
  f.parser->parse_does = two_candidates;
  const sdk::ParseResult want = two_candidates(f.request);
  const sdk::ParseResult got = kernel::checked_parse(f.ref, f.request);
  REQUIRE(got.candidates.size() == 2u);
  CHECK(got.derivations == 4242u);
  CHECK_FALSE(got.stopped);
  for (std::size_t i = 0; i < 2; ++i) {
    const sdk::Candidate &g = got.candidates[i], &w = want.candidates[i];
    CHECK(sdk::equal(g.program, w.program));
    CHECK(g.program->hash == w.program->hash);
    CHECK(g.program->size == w.program->size);
    CHECK(g.score == w.score);
    CHECK(g.core_only == w.core_only);
    CHECK(g.newest_rule == 12);
    REQUIRE(g.derivations.size() == 1u);
    const sdk::Derivation& d = *g.derivations[0];
    CHECK(d.start == 0);
    CHECK(d.end == 3);
    CHECK(d.score == -1e300);
    CHECK(d.rule->id == "r12");
    CHECK(d.rule->induced);
    CHECK(d.rule->how == sdk::RuleOrigin::alignment);
    CHECK(d.rule->author == "ann");
    CHECK(d.rule->head == "visit room1 twice");
    CHECK(d.rule->body == std::vector<std::string>{"visit room1", "visit room1"});
    CHECK(d.rule->created == -3);
    CHECK(d.rule->rhs == want.candidates[0].derivations[0]->rule->rhs);
    CHECK(sdk::equal(d.rule->sem, want.candidates[0].derivations[0]->rule->sem));
    REQUIRE(d.kids.size() == 1u);
    CHECK(d.kids[0]->score == 0.6);
    CHECK(d.kids[0]->rule->id == "core:7");
    CHECK_FALSE(d.kids[0]->rule->induced);
  }
  // What the child shared stays shared: one derivation object for both candidates, one leaf
  // for the kid and the chart, one rule object under both derivations' rules where it was one.
  CHECK(got.candidates[0].derivations[0] == got.candidates[1].derivations[0]);
  REQUIRE(got.chart.size() == 1u);
  CHECK(got.chart[0] == got.candidates[0].derivations[0]->kids[0]);
  CHECK(got.candidates[0].program == got.candidates[1].program);
}

TEST_CASE("an isolated parse is checked after the pipe, as in process", "[isolation][parser]") {
  Fixture f;
  for (const bool isolated : {true, false}) {
    const auto ref =
        f.ref.with_isolation(isolated ? kernel::Isolation::process : kernel::Isolation::in_process);
    f.parser->parse_does = [](const sdk::ParseRequest& r) {
      sdk::ParseResult out = two_candidates(r);
      auto far = std::make_shared<sdk::Derivation>(*out.chart[0]);
      far->end = 4;  // one token past "visit room1 twice"
      out.chart = {far};
      return out;
    };
    CHECK(error_of([&] { (void)kernel::checked_parse(ref, f.request); }) ==
          std::pair<std::string, std::string>{
              "invalid_candidate",
              "plugin 'scripted' (/p/libs.so): the chart: a derivation spans "
              "tokens [0, 4), outside [0, 3)"});
    f.parser->parse_does = [](const sdk::ParseRequest& r) {
      sdk::ParseResult out = two_candidates(r);
      out.candidates[1].score = std::numeric_limits<double>::infinity();
      return out;
    };
    CHECK(error_of([&] { (void)kernel::checked_parse(ref, f.request); }) ==
          std::pair<std::string, std::string>{
              "invalid_score", "plugin 'scripted' (/p/libs.so): candidate 1 has the score inf"});
  }
}

TEST_CASE("a parse, or its scorer within it, that crashes is plugin_crashed naming the parse",
          "[isolation][parser]") {
  Fixture f;
  f.parser->parse_does = [](const sdk::ParseRequest&) -> sdk::ParseResult { std::abort(); };
  CHECK(error_of([&] { (void)kernel::checked_parse(f.ref, f.request); }) ==
        std::pair<std::string, std::string>{"plugin_crashed",
                                            "plugin 'scripted' (/p/libs.so): parse: SIGABRT"});
  f.parser->parse_does = two_candidates;
  f.scorer.crash = true;
  CHECK(error_of([&] { (void)kernel::checked_parse(f.ref, f.request); }) ==
        std::pair<std::string, std::string>{"plugin_crashed",
                                            "plugin 'scripted' (/p/libs.so): parse: SIGSEGV"});
  // This process is intact: the next parse is answered.
  f.scorer.crash = false;
  CHECK(kernel::checked_parse(f.ref, f.request).candidates.size() == 2u);
}

TEST_CASE("parse result bytes that are not one whole answer are refused", "[isolation][parser]") {
  Fixture f;
  const std::string bytes = sdk::host::to_bytes(two_candidates(f.request));
  REQUIRE(sdk::host::parse_result_of(bytes).has_value());
  // Every proper prefix, and one byte more.
  for (std::size_t n = 0; n < bytes.size(); ++n)
    CHECK_FALSE(sdk::host::parse_result_of(bytes.substr(0, n)).has_value());
  CHECK_FALSE(sdk::host::parse_result_of(bytes + '\0').has_value());

  // A chain of program nodes nested 10000 deep is read; 10001 deep is not (bounded recursion).
  auto chain = [](std::uint64_t depth) {
    std::string b;
    auto put = [&](auto v) { b.append(reinterpret_cast<const char*>(&v), sizeof v); };
    put(depth);  // nodes
    for (std::uint64_t i = 0; i < depth; ++i) {
      put(static_cast<std::uint8_t>(sdk::Kind::CondNot));
      put(static_cast<std::uint8_t>(sdk::Sort::Condition));
      put(0.0);
      put(std::uint64_t{0});  // text
      put(std::int32_t{-1});
      put(std::uint64_t{0});                 // hash
      put(std::uint32_t{1});                 // size
      put(std::uint64_t{i == 0 ? 0u : 1u});  // kids
      if (i > 0) put(i);                     // the node before
    }
    for (int table = 0; table < 2; ++table) put(std::uint64_t{0});  // rules, derivations
    put(std::uint64_t{0});                                          // candidates
    put(std::uint64_t{0});                                          // chart
    put(std::uint8_t{0});
    put(std::uint64_t{0});
    return b;
  };
  CHECK(sdk::host::parse_result_of(chain(10000)).has_value());
  CHECK_FALSE(sdk::host::parse_result_of(chain(10001)).has_value());
  // An enumeration value past the last (Kind 55) is refused.
  std::string bad = chain(1);
  bad[8] = 55;
  CHECK_FALSE(sdk::host::parse_result_of(bad).has_value());
  bad[8] = 54;
  CHECK(sdk::host::parse_result_of(bad).has_value());
}
