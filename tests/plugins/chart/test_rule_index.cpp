// The rule index (flipper/toolkit/rule_index.hpp, start_rules.hpp; docs/naturalization.md §2,
// "Rule selection"), against brute force over the sdk::Rule objects themselves: StartRules hands
// out exactly the live, visible rules whose first symbol fits position i and whose later terminals
// occur far enough after it, in the order they were added; the exhaustive mode (the unindexed
// matcher) hands out every live rule whose first symbol fits; anchors are the rarest later tokens.
#include <catch2/catch.hpp>
#include <random>

#include "flipper/toolkit/rule_index.hpp"
#include "flipper/toolkit/start_rules.hpp"
#include "synthetic_rules.hpp"

using namespace flipper;
using indextest::induced_rule;
using indextest::synthetic_rules;
using toolkit::FirstKind;
using toolkit::RuleIndex;
using toolkit::StartRules;

namespace {

const std::vector<std::string> kWords = {"go", "to", "the", "red", "box", "and", "then", "up"};
const sdk::Symbol::Type kClasses[] = {sdk::Symbol::Type::number, sdk::Symbol::Type::color,
                                      sdk::Symbol::Type::shape, sdk::Symbol::Type::direction};

std::shared_ptr<const sdk::Grammar> small_grammar() {
  auto g = std::make_shared<sdk::Grammar>(
      sdk::parse_grammar("$ROOT -> $Action => $1\n"
                         "$Action -> $Action ; $Action => {$1;$2}\n"
                         "$Action -> move $Direction => {move $1}\n"
                         "$Direction -> @direction\n"
                         "$Number -> @number\n"
                         "$Area -> room1 => room1\n",
                         "small", {"red", "blue", "green"}, {"circle", "square"}));
  return g;
}

bool fits(const sdk::Grammar& g, const sdk::Symbol& s, const std::string& token) {
  if (s.type == sdk::Symbol::Type::token) return s.text == token;
  if (s.type == sdk::Symbol::Type::category) return false;
  return sdk::class_matches(g, s.type, token);
}

// Brute force: the rule's later terminals each occur at or after i + k.
bool may_start(const sdk::Grammar& g, const sdk::Rule& r, const std::vector<std::string>& toks,
               std::size_t i) {
  if (r.rhs.size() > toks.size() - i) return false;
  for (std::size_t k = 1; k < r.rhs.size(); ++k) {
    if (r.rhs[k].type == sdk::Symbol::Type::category) continue;
    bool seen = false;
    for (std::size_t p = i + k; p < toks.size() && !seen; ++p) seen = fits(g, r.rhs[k], toks[p]);
    if (!seen) return false;
  }
  return true;
}

// The selection of one (position, group) as Rule pointers, in index order.
std::vector<const sdk::Rule*> selection(const RuleIndex& index, StartRules& starts, int i,
                                        FirstKind kind, int first) {
  std::vector<const sdk::Rule*> out;
  for (int r : starts.at(i, kind, first))
    out.push_back(index.rules()[static_cast<std::size_t>(r)].rule.get());
  return out;
}

struct Group {
  FirstKind kind;
  int first;
  std::function<bool(const sdk::Rule&)> member;  // the first symbol fits the group
};

// Every group that can start at token i: its token, its classes, every category.
std::vector<Group> groups_at(const RuleIndex& index, const std::vector<std::string>& toks,
                             std::size_t i, const std::vector<std::string>& categories) {
  std::vector<Group> out;
  const std::string& t = toks[i];
  if (int id = index.token_id(t); id >= 0)
    out.push_back({FirstKind::token, id, [t](const sdk::Rule& r) {
                     return r.rhs[0].type == sdk::Symbol::Type::token && r.rhs[0].text == t;
                   }});
  for (int b = 0; b < 4; ++b)
    if (sdk::class_matches(index.grammar(), kClasses[b], t))
      out.push_back(
          {FirstKind::klass, b, [b](const sdk::Rule& r) { return r.rhs[0].type == kClasses[b]; }});
  for (const auto& c : categories)
    if (int id = index.category_id(c); id >= 0)
      out.push_back({FirstKind::category, id, [c](const sdk::Rule& r) {
                       return r.rhs.size() > 1 && r.rhs[0].type == sdk::Symbol::Type::category &&
                              r.rhs[0].text == c;
                     }});
  return out;
}

// Checks every (position, group) of `toks` against brute force over `live` (in add order).
// Returns how many rules were selected in all.
std::size_t check_utterance(const RuleIndex& index, const std::vector<sdk::RulePtr>& live,
                            const std::vector<std::string>& toks,
                            const StartRules::Visible& visible) {
  const auto ids = index.token_ids(toks);
  const auto classes = index.classes(toks);
  StartRules indexed(index, ids, classes, visible, false);
  StartRules exhaustive(index, ids, classes, visible, true);
  const std::vector<std::string> categories = {"$Action", "$Area", "$Number", "$Direction",
                                               "$ROOT"};
  std::size_t selected = 0;
  for (std::size_t i = 0; i < toks.size(); ++i)
    for (const auto& g : groups_at(index, toks, i, categories)) {
      std::vector<const sdk::Rule*> all, fitting;
      for (const auto& r : live) {
        if (!g.member(*r) || (visible && !visible(*r))) continue;
        all.push_back(r.get());
        if (may_start(index.grammar(), *r, toks, i)) fitting.push_back(r.get());
      }
      std::string text;
      for (const auto& t : toks) text += t + " ";
      INFO("utterance '" << text << "' position " << i << " group " << static_cast<int>(g.kind)
                         << "/" << g.first);
      CHECK(selection(index, indexed, static_cast<int>(i), g.kind, g.first) == fitting);
      CHECK(selection(index, exhaustive, static_cast<int>(i), g.kind, g.first) == all);
      selected += fitting.size();
    }
  return selected;
}

std::vector<std::string> random_utterance(std::mt19937& rng) {
  static const std::vector<std::string> extra = {"3", "red", "square", "left", "xyz", ";"};
  std::vector<std::string> toks(1 + rng() % 10);
  for (auto& t : toks)
    t = rng() % 4 == 0 ? extra[rng() % extra.size()] : kWords[rng() % kWords.size()];
  return toks;
}

}  // namespace

TEST_CASE("StartRules selects exactly the rules brute force says may start at each position") {
  RuleIndex index;
  auto g = small_grammar();
  index.reset(g);
  std::vector<sdk::RulePtr> live(g->rules.begin(), g->rules.end());
  for (auto& r : synthetic_rules(3000, kWords, 7)) {
    index.add(r);
    live.push_back(r);
  }
  // The grammar reader allows a class only as a whole RHS; the index takes classes anywhere.
  for (int k = 0; k < 40; ++k) {
    auto r = std::make_shared<sdk::Rule>();
    r->id = "c" + std::to_string(k);
    r->lhs = "$Action";
    const auto word = [&] { return sdk::Symbol{sdk::Symbol::Type::token, kWords[k % 8]}; };
    const sdk::Symbol klass{kClasses[k % 4], "@class"};
    r->rhs = k % 2 ? std::vector<sdk::Symbol>{klass, word(), klass}
                   : std::vector<sdk::Symbol>{word(), klass, word()};
    index.add(r);
    live.push_back(r);
  }
  std::mt19937 rng(11);
  std::size_t selected = 0;
  for (int u = 0; u < 150; ++u) selected += check_utterance(index, live, random_utterance(rng), {});

  SECTION("after removals and replacements (an id added again replaces its rule)") {
    for (int k = 7; k <= 3000; k += 7) {
      const std::string id = "s" + std::to_string(k);
      index.remove(id);
      live.erase(std::find_if(live.begin(), live.end(), [&](auto& r) { return r->id == id; }));
    }
    index.remove("s7");       // already gone: ignored
    index.remove("no-such");  // unknown: ignored
    std::mt19937 lines(3);
    for (int k = 11; k <= 3000; k += 11) {
      const std::string id = "s" + std::to_string(k);
      auto word = [&] { return kWords[lines() % kWords.size()]; };
      auto r = induced_rule(indextest::synthetic_line(k % 10, word), id, 5000 + k, "u9");
      index.add(r);
      auto old = std::find_if(live.begin(), live.end(), [&](auto& x) { return x->id == id; });
      if (old != live.end()) live.erase(old);
      live.push_back(r);
    }
    for (int u = 0; u < 150; ++u) check_utterance(index, live, random_utterance(rng), {});
  }
  SECTION("with a visibility filter") {
    const auto not_u2_fn = [](const sdk::Rule& r) { return r.author != "u2"; };
    const StartRules::Visible not_u2 = StartRules::Visible::of(not_u2_fn);
    for (int u = 0; u < 150; ++u) check_utterance(index, live, random_utterance(rng), not_u2);
  }
  // Not vacuous: the random utterances select rules (brute force's count, summed).
  CHECK(selected > 1000);
}

TEST_CASE("a rule's anchor is its later token fewest rules had when it was added") {
  RuleIndex index;
  index.reset(small_grammar());
  // The anchor of the rule, as the token it names ("" for none).
  auto anchor_of = [&](const std::string& line, const std::string& id) -> std::string {
    index.add(induced_rule(line, id, 1, "u"));
    const int a = index.rules().back().anchor;
    if (a < 0) return "";
    for (const std::string t : {"go", "to", "red", "box", "then"})
      if (index.token_id(t) == a) return t;
    return "?";
  };
  // Hand-computed: the counts of later-token uses before each rule; ties go to the leftmost.
  CHECK(anchor_of("$Action -> go to red => {move left}", "a") == "to");   // to 0, red 0
  CHECK(anchor_of("$Action -> go to box => {move left}", "b") == "box");  // to 1, box 0
  CHECK(anchor_of("$Action -> go box to => {move left}", "c") == "box");  // box 1, to 2
  CHECK(anchor_of("$Action -> go $Action => {move left}", "d") == "");
  CHECK(anchor_of("$Action -> $Action then $Action => {$1;$2}", "e") == "then");
  CHECK(anchor_of("$Action -> $Number red => {repeat $1 times {move left}}", "f") == "red");
  // The first symbol is the bucket, not a later token: `go` has no later uses yet.
  CHECK(anchor_of("$Action -> go to go => {move left}", "g") == "go");  // to 3, go 0
}
