// The repair suggestions' hit rate (flipper/replay/repair_hits.hpp, docs/replay.md "Repair
// suggestions"): the counting rule on hand-made rows (the three-query window at its boundary,
// a hit by text, by program, a miss), and the dev split's figure, pinned exactly (the README
// block `flipper replay repair` prints the same numbers).
#include <catch2/catch.hpp>

#include "flipper/replay/corpus.hpp"
#include "flipper/replay/repair_hits.hpp"
#include "flipper/replay/replayer.hpp"

using namespace flipper::replay;

namespace {

Command q(const std::string& qid, const std::string& text, const std::string& status) {
  Command c;
  c.qid = qid;
  c.kind = "q";
  c.user = "u";
  c.utterance = text;
  c.status = status;
  return c;
}

Command accept(const std::string& for_qid, const std::string& formula) {
  Command c;
  c.qid = "a" + for_qid;
  c.kind = "accept";
  c.user = "u";
  c.for_qid = for_qid;
  c.formula = formula;
  return c;
}

QueryRow row(const std::string& qid, const std::string& ours,
             std::vector<std::string> suggestions = {}, std::vector<std::string> formulas = {}) {
  QueryRow r;
  r.qid = qid;
  r.ours = ours;
  r.suggestions = std::move(suggestions);
  r.suggestion_formulas = std::move(formulas);
  return r;
}

}  // namespace

TEST_CASE("repair hits: the window, text and program hits, misses", "[replay][repair]") {
  Corpus c;
  // f1 fails; f2..f4 are its next three queries, f4 accepted: a case (window 3, at the bound).
  // f5 fails; its next three (f6..f8) have no accept: no case (f9 is its 4th). f6 fails; f9,
  // accepted, is its 3rd: a case.
  c.commands = {q("f1", "move up 3times", "Nothing"), q("f2", "move up thrice", "Nothing"),
                q("f3", "move up again", "Nothing"),  q("f4", "Move Up", "Core"),
                accept("f4", "(: move up)"),          q("f5", "vist room1", "Nothing"),
                q("f6", "go room1", "Nothing"),       q("f7", "move down", "Core"),
                q("f8", "move right", "Core"),        q("f9", "visit room1", "Core"),
                accept("f9", "(: visitArea room1)")};
  c.runs = {{"run", "B", {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10}}};
  c.answers["f9"].candidates = {{"{visit room1}", "(: visitArea room1)", true, nullptr}};
  ReplayResult r;
  r.runs = {"run"};
  SECTION("hits by text and by program") {
    r.queries = {row("f1", "unparsable", {"move right", "move up"}, {"{move right}", "{move up}"}),
                 row("f2", "unparsable", {"x"}, {"{move right}"}),
                 row("f3", "unparsable"),  // no suggestion
                 row("f5", "unparsable", {"visit room1"}, {"{visit room1}"}),
                 row("f6", "unparsable", {"room1 visit"}, {"{visit room1}"})};
    const RepairHits h = repair_hits(c, r);
    // Cases: f1, f2, f3 (f4 within three), f6 (f9 its third); not f5, whose suggestion would hit.
    CHECK(h.cases == 4);
    CHECK(h.repaired == 4);
    CHECK(h.with_suggestions == 3);
    CHECK(h.hits == 2);     // f1 by its tokens ("Move Up"), f6 by its program
    CHECK(h.by_text == 1);  // f2's "x" is neither
    CHECK(h.by_program == 1);
  }
  SECTION("only the top three suggestions count; parsed and refused queries are counted apart") {
    r.queries = {row("f1", "unparsable", {"a", "b", "c", "move up"}), row("f2", "core"),
                 row("f3", "error"), row("f6", "unparsable", {"a", "b", "visit room1"})};
    const RepairHits h = repair_hits(c, r);
    CHECK(h.cases == 4);
    CHECK(h.we_parse == 1);
    CHECK(h.errors == 1);
    CHECK(h.repaired == 2);
    CHECK(h.hits == 1);  // f6's third; f1's fourth is out
  }
}

TEST_CASE("the dev split's repair hit rate", "[replay][repair][dev]") {
  const Corpus corpus = load_corpus(FLIPPER_STUDY_DIR "/dev");
  ReplayOptions o;
  o.sets = {"induction.generalize=false"};
  o.repair = true;
  const RepairHits h = repair_hits(corpus, replay(corpus, o));
  CHECK(h.cases == 323);
  CHECK(h.we_parse == 6);
  CHECK(h.errors == 0);
  CHECK(h.repaired == 317);
  CHECK(h.with_suggestions == 192);
  CHECK(h.hits == 71);
  CHECK(h.by_text == 64);
  CHECK(h.by_program == 7);
}
