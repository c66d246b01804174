// Metric code on hand-made rows, the SVG writer, and the deletion mapping on the dev split.
#include <catch2/catch.hpp>

#include "flipper/replay/corpus.hpp"
#include "flipper/replay/deletion_map.hpp"
#include "flipper/replay/metrics.hpp"
#include "flipper/replay/output.hpp"
#include "flipper/replay/rule_oracle.hpp"

using namespace flipper::replay;

namespace {
QueryRow row(std::string group, std::string user, int tokens, std::string orig, std::string ours,
             std::string orig_author = "", std::string our_author = "none") {
  QueryRow r;
  r.group = std::move(group);
  r.user = std::move(user);
  r.phase = "task";
  r.in_authors_tables = true;
  r.tokens = tokens;
  r.original = std::move(orig);
  r.ours = std::move(ours);
  r.original_author = std::move(orig_author);
  r.our_author = std::move(our_author);
  return r;
}
}  // namespace

TEST_CASE("figures count tokens, statuses and authors per participant") {
  std::vector<QueryRow> rows = {
      row("B", "u1", 3, "Core", "core"),
      row("B", "u1", 4, "Induced", "unparsable", "Self"),
      row("B", "u2", 5, "Nothing", "induced", "", "self"),
      row("C", "c1", 2, "Induced", "induced", "Other", "other"),
      row("C", "c1", 6, "Induced", "induced", "Self", "other"),
      row("C", "c2", 1, "Nothing", "error"),
  };
  QueryRow warm = row("B", "u1", 100, "Core", "core");
  warm.phase = "warmup";
  rows.push_back(warm);

  const Figures ours = figures(rows, true), orig = figures(rows, false);
  CHECK(ours.tokens_all_sum.at("B") == 12);
  CHECK(ours.tokens_successful_sum.at("B") == 8);  // 3 + 5
  CHECK(orig.tokens_successful_sum.at("B") == 7);  // 3 + 4
  CHECK(ours.tokens_successful.at("B").mean == Approx(4.0));
  CHECK(ours.tokens_all.at("C").mean == Approx(4.5));
  CHECK(ours.induced.at("B").mean == Approx(0.5));
  CHECK(ours.induced.at("B").min == 0);
  CHECK(ours.induced.at("B").max == 1);
  CHECK(orig.core.at("B").mean == Approx(0.5));
  CHECK(ours.others.mean == Approx(1.0));  // c1: 2, c2: 0
  CHECK(ours.self.mean == Approx(0.0));
  CHECK(orig.others.mean == Approx(0.5));
  CHECK(orig.self.mean == Approx(0.5));
  REQUIRE(ours.participants.size() == 4);
  CHECK(ours.participants[0].user == "u1");
  CHECK(ours.participants[0].agree == 1);

  const Agreement a = agreement(rows);
  CHECK(a.n == 7);
  CHECK(a.agree == 5);  // an error (refused input) agrees with the original's Nothing
  CHECK(a.confusion.at("Nothing").at("error") == 1);
  CHECK(a.confusion.at("Induced").at("unparsable") == 1);
}

TEST_CASE("execution agreement counts accept classes and the unexplained ones") {
  auto accept = [](bool compared, bool all, std::string diff) {
    AcceptRow r;
    r.matched = r.executed = compared;
    r.compared = compared;
    r.robot = r.held = r.floor = all;
    r.diff = std::move(diff);
    return r;
  };
  const std::vector<AcceptRow> rows = {
      accept(true, true, "agree"),
      accept(true, true, "agree"),
      accept(true, false, "loop_order"),
      accept(true, false, "unexplained"),
      accept(false, false, "budget_exceeded"),  // failed, next world known
      accept(true, false, "start_differs"),
      accept(true, false, "made_up"),
      accept(false, false, "")};  // not matched
  const ExecAgreement e = exec_agreement(rows);
  CHECK(e.accepts == 8);
  CHECK(e.compared == 6);
  CHECK(e.all == 2);
  CHECK(e.classified == 7);
  CHECK(e.classes == std::map<std::string, int>{{"agree", 2},
                                                {"budget_exceeded", 1},
                                                {"loop_order", 1},
                                                {"made_up", 1},
                                                {"start_differs", 1},
                                                {"unexplained", 1}});
  CHECK(e.unexplained == 3);  // unexplained, start_differs and the unknown id
  CHECK(e.not_executed == std::map<std::string, int>{{"unknown", 2}});
  Metrics m;
  m.exec = e;
  const auto j = metrics_json(m);
  CHECK(j["execution"]["classes"]["loop_order"] == 1);
  CHECK(j["execution"]["unexplained"] == 3);
}

TEST_CASE("latency histogram uses half-decade bins") {
  Latency l = latency({0.5, 50, 50, 2000, 1e9});
  CHECK(l.histogram[3] == 1);   // [0.316, 1)
  CHECK(l.histogram[7] == 2);   // [31.6, 100)
  CHECK(l.histogram[10] == 1);  // [1000, 3162)
  CHECK(l.histogram.back() == 1);
  CHECK(l.p50 == 50);
}

TEST_CASE("dev split deletions map to the definitions that lost rules") {
  const Corpus corpus = load_corpus(FLIPPER_STUDY_DIR "/dev");
  const std::string run = "sep2018/FridayMorningC";
  DeletionMap map;
  for (const Definition* d : corpus.preloaded(run)) map.add_definition(*d, d->author(), {});
  std::vector<std::string> mapped;
  for (const auto& c : corpus.commands) {
    if (c.source != run) continue;
    if (c.kind.rfind("def", 0) == 0) {
      const auto& d = corpus.definitions[corpus.definition_index.at(c.def_id)];
      map.add_definition(d, c.user,
                         {{"r-" + c.qid + "-s", "simple"}, {"r-" + c.qid + "-b", "best"}});
    } else if (c.kind == "delete") {
      mapped.push_back(map.map(c.user, c.rule_index).ids.at(0));
    }
  }
  // #853 lost both rules (none in the final log); #961 and #1313 kept only their simple rule.
  CHECK(mapped == std::vector<std::string>{"r-" + run + "#853-s", "r-" + run + "#853-b",
                                           "r-" + run + "#961-b", "r-" + run + "#1313-b"});
}

TEST_CASE("rule oracle: identical, subset, overlap, missing", "[replay][defects]") {
  using flipper::replay::compare_rules;
  using flipper::replay::LoggedRule;
  using flipper::replay::RuleShape;
  const LoggedRule simple{1, true, false, "$Action", {"pick", "any", "$Color", "item"}};
  const LoggedRule best{2, false, false, "$Action", {"$ItemActionFragment", "any", "$Property"}};
  const LoggedRule aligned{3, false, true, "$ItemActionFragment", {"grab"}};
  const RuleShape our_simple{"$Action", {"pick", "any", "$Color", "item"}};
  const RuleShape our_best{"$Action", {"$ItemAct", "any", "$Property"}};
  const RuleShape other{"$Action", {"pick", "any", "$Property", "item"}};
  CHECK(compare_rules({simple, best}, {our_simple, our_best}) == "identical");
  CHECK(compare_rules({simple, best, aligned}, {our_best, our_simple}) == "identical");
  CHECK(compare_rules({simple, best}, {our_best}) == "subset");
  CHECK(compare_rules({simple, best}, {our_best, other}) == "overlap");
  CHECK(compare_rules({simple, best}, {our_simple, our_best, other}) == "overlap");
  CHECK(compare_rules({simple, best}, {other}) == "missing");
  CHECK(compare_rules({simple, best}, {}) == "missing");
  CHECK(compare_rules({aligned}, {our_simple}).empty());
  CHECK(compare_rules({}, {our_simple}).empty());
  // Our alignment rules are left out as the original's are (the February runs' alignment,
  // docs/naturalization.md §4.8).
  const RuleShape our_aligned{"$CountedItem", {"all"}, "", true};
  CHECK(compare_rules({simple, best, aligned}, {our_simple, our_best, our_aligned}) == "identical");
}

TEST_CASE("rule oracle: a studio recording's rules are compared with their semantics",
          "[replay][defects]") {
  // docs/studio.md §7: every logged rule has semantics in our notation, alignment rules count.
  using flipper::replay::compare_rules;
  using flipper::replay::LoggedRule;
  using flipper::replay::RuleShape;
  const LoggedRule zig{1, true, false, "$Action", {"zig"}, "{{move right};{move up}}"};
  const LoggedRule grab{2, false, true, "$ItemAct", {"grab"}, "pick"};
  const RuleShape ours{"$Action", {"zig"}, "{{move right};{move up}}"};
  const RuleShape our_grab{"$ItemAct", {"grab"}, "pick"};
  const RuleShape other_reading{"$Action", {"zig"}, "{{move right};{move left}}"};
  CHECK(compare_rules({zig}, {ours}) == "identical");
  CHECK(compare_rules({zig}, {other_reading}) == "missing");  // same shape, another program
  CHECK(compare_rules({zig, grab}, {ours, our_grab}) == "identical");
  CHECK(compare_rules({zig, grab}, {ours}) == "subset");  // the alignment rule is compared too
}

TEST_CASE("rule identity: identical, present, subset, superset, overlap, disjoint, $Action hole",
          "[replay][defects]") {
  using flipper::replay::classify_rules;
  using flipper::replay::LoggedRule;
  using flipper::replay::RuleShape;
  const LoggedRule simple{1, true, false, "$Action", {"pick", "all", "items"}};
  const LoggedRule hole{2, false, false, "$Action", {"$Action", "items"}};
  const LoggedRule keyword{3, false, false, "KEYWORD_TOKEN", {"pick"}};
  const LoggedRule aligned{4, false, true, "$ItemActionFragment", {"grab"}};
  const RuleShape our_simple{"$Action", {"pick", "all", "items"}};
  const RuleShape our_hole{"$Action", {"$Action", "items"}};
  const RuleShape our_verb{"$Action", {"$ItemAct", "all", "items"}};
  auto cls = [](const std::vector<LoggedRule>& o, const std::vector<RuleShape>& ours,
                const std::vector<RuleShape>& present = {}) {
    const auto r = classify_rules(o, ours, present);
    return r.cls + (r.action_hole ? "+hole" : "");
  };
  // Keyword and alignment rules of the original are not compared.
  CHECK(cls({simple, hole, keyword, aligned}, {our_hole, our_simple}) == "identical");
  CHECK(cls({simple, hole}, {our_simple}, {our_hole}) == "present");
  CHECK(cls({simple, hole}, {}, {our_simple, our_hole}) == "present");
  CHECK(cls({simple, hole}, {our_simple}, {our_verb}) == "subset+hole");
  CHECK(cls({simple, hole}, {}) == "subset+hole");
  CHECK(cls({simple}, {our_simple, our_verb}) == "superset");
  CHECK(cls({simple, hole}, {our_simple, our_verb}) == "overlap+hole");
  CHECK(cls({simple, hole}, {our_simple, our_hole, our_verb}) == "superset");
  CHECK(cls({hole}, {our_verb}) == "disjoint+hole");
  CHECK(cls({simple}, {our_verb}) == "disjoint");
  // Our alignment rules are left out as the original's are.
  const RuleShape our_aligned{"$ItemAct", {"grab"}, "", true};
  CHECK(cls({simple}, {our_simple, our_aligned}) == "identical");
  CHECK(cls({keyword, aligned}, {our_simple}).empty());
  CHECK(cls({}, {our_simple}).empty());
}
