// Whole parses with the rule index against the unindexed matcher (the same plugin with
// rule_index=false, which tries every rule whose first symbol fits): on the distinct dev-corpus
// queries, with 0 / 1,000 synthetic induced rules over the corpus's own words (every query),
// 10,000 (every 4th or 8th) and 100,000 (every 40th), loaded at once or added and removed one by
// one, with and without a visibility filter, the candidates come out identical: programs, order,
// scores, flags, every derivation tree; for chart also the head chart and the derivation count
// (floating's count may drop: it no longer builds skip nodes for rules that cannot match). The
// parse loop both sides share is held to the original's recorded answers by test_probes.cpp.
#include <catch2/catch.hpp>
#include <cstdio>
#include <functional>
#include <iostream>
#include <map>
#include <random>

#include "flipper/sdk/parser.hpp"
#include "plugin_fixture.hpp"
#include "synthetic_rules.hpp"

using namespace flipper;

namespace {

std::shared_ptr<const sdk::Grammar> core_grammar() {
  static const auto g = std::make_shared<const sdk::Grammar>(sdk::load_grammar_file(
      std::string(FLIPPER_SOURCE_DIR) + "/configs/grammars/core.grammar",
      {"black", "blue", "gray", "green", "orange", "pink", "purple", "red", "yellow"},
      {"triangle", "circle", "square"}, {"up", "down", "left", "right"}));
  return g;
}

const std::vector<std::string>& utterances() {
  static const auto u = indextest::dev_utterances();
  return u;
}

const std::vector<sdk::RulePtr>& rules(int n) {
  static std::map<int, std::vector<sdk::RulePtr>> cache;
  auto& r = cache[n];
  if (r.empty() && n > 0)
    r = indextest::synthetic_rules(n, indextest::frequent_words(utterances(), 120), 2024);
  return r;
}

std::string num(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

void tree(const sdk::Derivation& d, std::string& out) {
  out += "(" + d.rule->id + "[" + std::to_string(d.start) + "," + std::to_string(d.end) + "] " +
         num(d.score);
  for (const auto& k : d.kids) {
    out += " ";
    tree(*k, out);
  }
  out += ")";
}

// Everything a caller sees of a parse, as text.
std::string transcript(const sdk::ParseResult& r, bool with_count) {
  std::string out = r.stopped ? "stopped\n" : "";
  if (with_count) out += "derivations " + std::to_string(r.derivations) + "\n";
  for (const auto& c : r.candidates) {
    out += sdk::render(c.program) + " " + num(c.score) + (c.core_only ? " core " : " induced ") +
           std::to_string(c.newest_rule) + "\n";
    for (const auto& d : c.derivations) {
      out += "  ";
      tree(*d, out);
      out += "\n";
    }
  }
  for (const auto& d : r.chart) {
    out += "chart ";
    tree(*d, out);
    out += "\n";
  }
  return out;
}

struct Pair {
  using StartVisible = std::function<bool(const sdk::Rule&)>;
  std::string name;
  std::shared_ptr<sdk::Parser> indexed, oracle;
  std::shared_ptr<sdk::Scorer> scorer = testsupport::load_plugin<sdk::Scorer>("loglinear");

  explicit Pair(const std::string& plugin)
      : name(plugin),
        indexed(testsupport::load_plugin<sdk::Parser>(plugin)),
        oracle(testsupport::load_plugin<sdk::Parser>(
            plugin, sdk::Params(std::map<std::string, sdk::ParamValue>{{"rule_index", false}}))) {}

  void set_grammar(int n) {
    auto g = std::make_shared<sdk::Grammar>(*core_grammar());
    g->rules.insert(g->rules.end(), rules(n).begin(), rules(n).end());
    indexed->set_grammar(g);
    oracle->set_grammar(g);
  }
  void add(const sdk::RulePtr& r) {
    indexed->add_rule(r);
    oracle->add_rule(r);
  }
  void remove(const std::string& id) {
    indexed->remove_rule(id);
    oracle->remove_rule(id);
  }

  // Parses every `step`-th utterance with both; returns the number that differ (printing the
  // first) and counts the utterances with an induced candidate.
  int compare(std::size_t step, const StartVisible& visible, bool want_chart,
              int* with_induced = nullptr) const {
    int differ = 0;
    for (std::size_t k = 0; k < utterances().size(); k += step) {
      sdk::ParseRequest req;
      req.tokens = sdk::tokenize(utterances()[k]);
      req.scorer = scorer.get();
      req.context.user = "u1";
      req.visible = sdk::RuleFilter::of(visible);
      req.want_chart = want_chart;
      const auto a = indexed->parse(req);
      const auto b = oracle->parse(req);
      const bool count = name == "chart";
      if (transcript(a, count) != transcript(b, count)) {
        if (differ++ == 0)
          std::cout << name << " differs on '" << utterances()[k] << "'\nindexed:\n"
                    << transcript(a, count) << "unindexed:\n"
                    << transcript(b, count);
      }
      if (with_induced)
        for (const auto& c : a.candidates)
          if (c.newest_rule > 0) {
            ++*with_induced;
            break;
          }
    }
    return differ;
  }
};

}  // namespace

TEST_CASE("chart and floating: the rule index changes no parse of the dev corpus") {
  // The unindexed matcher is slow with 10,000 rules (that is why there is an index): every
  // 4th (chart) or 8th (floating) query there.
  for (const char* plugin : {"chart", "floating"}) {
    Pair p(plugin);
    const bool chart = p.name == "chart";
    for (int n : {0, 1000, 10000}) {
      INFO(plugin << " with " << n << " synthetic rules");
      p.set_grammar(n);
      const std::size_t step = n < 10000 ? 1 : chart ? 4 : 8;
      int with_induced = 0;
      CHECK(p.compare(step, {}, false, &with_induced) == 0);
      // Not vacuous: the synthetic rules take part in real queries (0 rules: none can).
      if (n == 0)
        CHECK(with_induced == 0);
      else
        CHECK(with_induced > 20);
      CHECK(p.compare(step * 7, {}, true) == 0);  // head charts too
    }
  }
}

TEST_CASE("the rule index changes no parse when rules come and go one by one, or are hidden") {
  for (const char* plugin : {"chart", "floating"}) {
    INFO(plugin);
    Pair p(plugin);
    p.set_grammar(0);
    for (const auto& r : rules(1000)) p.add(r);
    for (int k = 3; k <= 1000; k += 3) p.remove("s" + std::to_string(k));
    std::mt19937 rng(5);
    const auto words = indextest::frequent_words(utterances(), 120);
    for (int k = 4; k <= 1000; k += 8)  // the same id again: replaces the rule
      p.add(indextest::induced_rule(
          indextest::synthetic_line(k % 10, [&] { return words[rng() % words.size()]; }),
          "s" + std::to_string(k), 2000 + k, "u3"));
    CHECK(p.compare(1, {}, false) == 0);
    const Pair::StartVisible hide_u2 = [](const sdk::Rule& r) { return r.author != "u2"; };
    CHECK(p.compare(1, hide_u2, false) == 0);
  }
}

TEST_CASE("chart: the rule index changes no parse with 100,000 rules") {
  Pair p("chart");
  p.set_grammar(100000);
  int with_induced = 0;
  CHECK(p.compare(40, {}, false, &with_induced) == 0);
  CHECK(with_induced > 2);
}
