// Parse latency over every dev-corpus `q` utterance with 0, 1,000 and 10,000 induced rules
// (generated like real definitions: `pick $Number <w> items`, `visit $Color $Shape <w>`, ...),
// for the exact `chart` parser and the skip-tolerant `floating` parser (default params).
// Prints p50 / p99 / max per parser and grammar size (median of 3 runs per utterance).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/parser.hpp"
#include "plugin_fixture.hpp"

using namespace flipper;

namespace {

std::shared_ptr<const sdk::Grammar> core() {
  return std::make_shared<const sdk::Grammar>(sdk::load_grammar_file(
      std::string(FLIPPER_SOURCE_DIR) + "/configs/grammars/core.grammar",
      {"black", "blue", "gray", "green", "orange", "pink", "purple", "red", "yellow"},
      {"triangle", "circle", "square"}, {"up", "down", "left", "right"}));
}

sdk::RulePtr rule(int i, const std::vector<std::string>& rhs, const std::string& tmpl) {
  auto r = std::make_shared<sdk::Rule>();
  r->id = "bench:" + std::to_string(i);
  r->lhs = "$Action";
  std::vector<sdk::Sort> holes;
  for (const auto& w : rhs) {
    sdk::Symbol s{w[0] == '$' ? sdk::Symbol::Type::category : sdk::Symbol::Type::token, w};
    if (w[0] == '$') holes.push_back(sdk::category_sort(w));
    r->rhs.push_back(s);
  }
  r->sem = sdk::read_template(tmpl, sdk::Sort::Action, holes);
  r->induced = true;
  r->how = sdk::RuleOrigin::best;
  r->author = "user" + std::to_string(i % 37);
  r->created = i + 1;
  return r;
}

// Realistic shapes; words mix corpus vocabulary with generated ones.
std::vector<sdk::RulePtr> induced_rules(int n) {
  const std::vector<std::string> common = {"pick",  "drop", "visit", "move", "go",  "all",  "the",
                                           "items", "red",  "room1", "to",   "and", "then", "left"};
  std::mt19937 rng(42);
  auto word = [&](int i) {
    return rng() % 3 == 0 ? common[rng() % common.size()] : "w" + std::to_string(i % 997) + "x";
  };
  std::vector<sdk::RulePtr> out;
  for (int i = 0; i < n; ++i) {
    switch (i % 5) {
      case 0:
        out.push_back(
            rule(i, {"pick", "$Number", word(i), "items"}, "{repeat $1 times {pick item}}"));
        break;
      case 1:
        out.push_back(rule(i, {"visit", "$Color", "$Shape", word(i)},
                           "{visit {world containing item {{is $1} and {is $2}}}}"));
        break;
      case 2:
        out.push_back(rule(i, {word(i), word(i + 1), "$Area"}, "{visit $1}"));
        break;
      case 3:
        out.push_back(rule(i, {word(i), "$Direction", word(i + 7)}, "{repeat 2 times {move $1}}"));
        break;
      default:
        out.push_back(rule(i, {"gather", "$Color", word(i)},
                           "{foreach point in {world containing item {is $1}} {{visit point};{pick "
                           "every item {is $1}}}}"));
    }
  }
  return out;
}

}  // namespace

int main() {
  std::vector<std::vector<std::string>> utterances;
  std::ifstream in(std::string(FLIPPER_STUDY_DIR) + "/dev/queries.jsonl");
  for (std::string line; std::getline(in, line);) {
    auto j = nlohmann::json::parse(line);
    if (j.value("kind", "") == "q" && j["utterance"].is_string())
      utterances.push_back(sdk::tokenize(j["utterance"].get<std::string>()));
  }
  if (utterances.empty()) {
    std::fprintf(stderr, "no dev-corpus utterances found\n");
    return 1;
  }
  auto scorer = testsupport::load_plugin<sdk::Scorer>("loglinear");
  for (const std::string name : {"chart", "floating"})
    for (int n : {0, 1000, 10000}) {
      auto parser = testsupport::load_plugin<sdk::Parser>(name);
      parser->set_grammar(core());
      for (auto& r : induced_rules(n)) parser->add_rule(r);
      std::vector<double> ms;
      std::size_t parsed = 0;
      for (const auto& toks : utterances) {
        sdk::ParseRequest req;
        req.tokens = toks;
        req.scorer = scorer.get();
        req.context.user = "user1";
        double runs[3];
        for (double& t : runs) {
          const auto t0 = std::chrono::steady_clock::now();
          auto r = parser->parse(req);
          t = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                  .count();
          if (&t == runs) parsed += r.candidates.empty() ? 0 : 1;
        }
        std::sort(runs, runs + 3);
        ms.push_back(runs[1]);
      }
      std::sort(ms.begin(), ms.end());
      auto pct = [&](double p) {
        return ms[std::min(ms.size() - 1,
                           static_cast<std::size_t>(p * static_cast<double>(ms.size())))];
      };
      std::printf(
          "%-8s induced=%5d utterances=%zu parsed=%zu  p50=%.3f ms  p99=%.3f ms  max=%.3f ms%s\n",
          name.c_str(), n, ms.size(), parsed, pct(0.5), pct(0.99), ms.back(),
          n == 10000 ? "  (target p99 <= 10 ms)" : "");
    }
}
