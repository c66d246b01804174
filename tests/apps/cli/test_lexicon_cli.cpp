// `flipper lexicon list|export|import` on stores written by `flipper session`: listing with and
// without --author, export -> import replays definitions (rules induced again, nothing stored
// replaced, a second import adds nothing), --restore copies verbatim into an empty store only.
#include "cli_test_support.hpp"
#include "flipper/naturalization/lexicon_store.hpp"

using namespace flipper::clitest;

namespace {

const char* kScript =
    R"({"op":"user","name":"ana"}
{"op":"define","head":"pick 3 items","body":["repeat 3 times pick item"]}
{"op":"user","name":"bob"}
{"op":"define","head":"zorkab left","body":["move left"]}
)";

/// A store holding ana's and bob's definitions, written by a real session.
std::string make_store(const std::string& name) {
  const std::string store = scratch(name);
  const std::string script = write_file(name + ".jsonl", kScript);
  const Run r = run_flipper("session --set lexicon.path=" + store + " " + script);
  INFO(r.out);
  REQUIRE(r.status == 0);
  REQUIRE(r.out.find("\"ok\":false") == std::string::npos);
  return store;
}

std::size_t lines_with(const std::string& text, const std::string& word) {
  std::size_t n = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) n += contains(line, word) ? 1 : 0;
  return n;
}

}  // namespace

TEST_CASE("lexicon list prints the rules, optionally of one author", "[cli][lexicon]") {
  const std::string store = make_store("list.sqlite");
  const Run all = run_flipper("lexicon list --set lexicon.path=" + store);
  INFO(all.out);
  REQUIRE(all.status == 0);
  CHECK(contains(all.out, "ID"));
  CHECK(contains(all.out, "AUTHOR"));
  CHECK(contains(all.out, " -> "));
  CHECK(contains(all.out, " => "));
  CHECK(contains(all.out, "{repeat"));
  CHECK(lines_with(all.out, " ana ") >= 1);
  CHECK(lines_with(all.out, " bob ") >= 1);

  const Run ana = run_flipper("lexicon list --author ana --set lexicon.path=" + store);
  INFO(ana.out);
  REQUIRE(ana.status == 0);
  CHECK(lines_with(ana.out, " ana ") >= 1);
  CHECK(lines_with(ana.out, " bob ") == 0);
  const Run nobody = run_flipper("lexicon list --author carol --set lexicon.path=" + store);
  CHECK(nobody.status == 0);
  CHECK(contains(nobody.out, "0 rules in"));
}

TEST_CASE("lexicon export then import replays the definitions through induction",
          "[cli][lexicon]") {
  const std::string source = make_store("export.sqlite");
  const std::string file = scratch("export.jsonl");
  const Run exported = run_flipper("lexicon export " + file + " --set lexicon.path=" + source);
  INFO(exported.out);
  REQUIRE(exported.status == 0);
  const std::string text = read_file(file);
  CHECK(lines_with(text, R"("type":"definition")") == 2);
  CHECK(lines_with(text, R"("type":"rule")") >= 2);
  // '-' writes the same to standard output.
  CHECK(run_flipper("lexicon export - --set lexicon.path=" + source, false).out == text);

  // The target already holds a definition of its own, which the import must keep.
  const std::string target = scratch("import.sqlite");
  const std::string own = write_file("own.jsonl", R"({"op":"user","name":"carol"}
{"op":"define","head":"zorkcd right","body":["move right"]}
)");
  REQUIRE(run_flipper("session --set lexicon.path=" + target + " " + own).status == 0);
  const Run imported = run_flipper("lexicon import " + file + " --set lexicon.path=" + target);
  INFO(imported.out);
  REQUIRE(imported.status == 0);
  CHECK(contains(imported.out, "imported 2 definitions"));
  CHECK(contains(imported.out, "0 already stored"));
  CHECK(contains(imported.out, "rule/weights lines not copied"));
  const Run listed = run_flipper("lexicon list --set lexicon.path=" + target);
  INFO(listed.out);
  CHECK(lines_with(listed.out, " ana ") >= 1);
  CHECK(lines_with(listed.out, " bob ") >= 1);
  CHECK(lines_with(listed.out, " carol ") >= 1);
  // Imported rules parse in a new session: ana's rule reads "drop 2 items".
  const std::string ask = write_file("ask.jsonl", R"({"op":"user","name":"dan"}
{"op":"query","text":"drop 2 items"}
)");
  const Run q = run_flipper("session --set lexicon.path=" + target + " " + ask, false);
  INFO(q.out);
  CHECK(contains(q.out, R"("status":"induced")"));

  // Importing again adds nothing.
  const Run again = run_flipper("lexicon import " + file + " --set lexicon.path=" + target);
  INFO(again.out);
  REQUIRE(again.status == 0);
  CHECK(contains(again.out, "imported 0 definitions"));
  CHECK(contains(again.out, "2 already stored"));
}

TEST_CASE("lexicon import --restore copies verbatim into an empty store only", "[cli][lexicon]") {
  const std::string source = make_store("restore-src.sqlite");
  const std::string file = scratch("restore.jsonl");
  REQUIRE(run_flipper("lexicon export " + file + " --set lexicon.path=" + source).status == 0);

  const std::string empty = scratch("restore-dst.sqlite");
  const Run restored =
      run_flipper("lexicon import --restore " + file + " --set lexicon.path=" + empty);
  INFO(restored.out);
  REQUIRE(restored.status == 0);
  CHECK(contains(restored.out, "restored"));
  const std::string copy = scratch("restore-copy.jsonl");
  REQUIRE(run_flipper("lexicon export " + copy + " --set lexicon.path=" + empty).status == 0);
  CHECK(read_file(copy) == read_file(file));  // rules, ids, counters, weights: identical

  // Into a non-empty store: refused, and the store is unchanged.
  const Run refused =
      run_flipper("lexicon import --restore " + file + " --set lexicon.path=" + empty);
  INFO(refused.out);
  CHECK(refused.status == 2);
  CHECK(contains(refused.out, "empty store only"));
  REQUIRE(run_flipper("lexicon export " + copy + " --set lexicon.path=" + empty).status == 0);
  CHECK(read_file(copy) == read_file(file));
}

TEST_CASE("lexicon commands refuse bad input with a clear message", "[cli][lexicon]") {
  const std::string missing = scratch("missing.sqlite");
  const Run list = run_flipper("lexicon list --set lexicon.path=" + missing);
  CHECK(list.status == 2);
  CHECK(contains(list.out, "no lexicon store at '" + missing + "'"));
  CHECK_FALSE(std::filesystem::exists(missing));  // reading never creates a store

  const std::string bad =
      write_file("bad.jsonl", "{\"head\":\"a\",\"body\":[\"move left\"]}\n{oops\n");
  const std::string target = scratch("bad-target.sqlite");
  const Run imported = run_flipper("lexicon import " + bad + " --set lexicon.path=" + target);
  INFO(imported.out);
  CHECK(imported.status == 2);
  CHECK(contains(imported.out, "bad.jsonl line 2"));
  CHECK(contains(imported.out, "bad_request"));

  const Run unreadable =
      run_flipper("lexicon import /nonexistent/x.jsonl --set lexicon.path=" + target);
  CHECK(unreadable.status == 2);
  CHECK(contains(unreadable.out, "cannot read '/nonexistent/x.jsonl'"));

  const Run restore_bad =
      run_flipper("lexicon import --restore " + bad + " --set lexicon.path=" + target);
  CHECK(restore_bad.status == 2);
  CHECK(contains(restore_bad.out, "lexicon import line 1"));
}

TEST_CASE("a stored rule that no longer loads is listed and exported as quarantined",
          "[cli][lexicon]") {
  const std::string store = make_store("quarantine.sqlite");
  {
    flipper::naturalization::LexiconStore raw(store);
    flipper::naturalization::StoredRule bad;
    bad.lhs = "$Action";
    bad.rhs = {"glorb", "$Bogus"};  // what a '$' head used to store
    bad.semantics = "{move left}";
    bad.author = "mallory";
    bad.head = "glorb $Bogus";
    bad.body = {"move left"};
    bad.how = "simple";
    raw.add_definition({0, bad.head, bad.body, bad.author, 1}, {bad});
  }
  const Run list = run_flipper("lexicon list --set lexicon.path=" + store);
  INFO(list.out);
  REQUIRE(list.status == 0);
  CHECK(lines_with(list.out, "QUARANTINED") == 1);
  CHECK(contains(list.out, "author 'mallory', head 'glorb $Bogus'"));
  CHECK(contains(list.out, "unknown category '$Bogus'"));
  CHECK(contains(list.out, "1 quarantined (not served)"));
  CHECK(lines_with(list.out, " mallory ") == 0);  // not among the live rules
  const Run exported = run_flipper("lexicon export - --set lexicon.path=" + store, false);
  REQUIRE(exported.status == 0);
  CHECK(lines_with(exported.out, "\"quarantined\":") == 1);
  // A session still opens the store, warns about the rule by name, and serves the others.
  const std::string script =
      write_file("quarantine.jsonl", R"({"op":"query","text":"zorkab left"})");
  const Run session = run_flipper("session --set lexicon.path=" + store + " " + script);
  INFO(session.out);
  REQUIRE(session.status == 0);
  CHECK(contains(session.out, "warning: lexicon store"));
  CHECK(contains(session.out, "is quarantined, not served"));
  CHECK(contains(session.out, "\"status\":\"induced\""));
}
