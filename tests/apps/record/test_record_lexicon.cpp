// A run's manifest names the lexicon it starts from (docs/experiments.md §2, docs/naturalization.md
// §5 "History and governance"): the store's checksum, last history entry and the tag naming it.
#include <catch2/catch.hpp>
#include <filesystem>

#include "flipper/kernel/config.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/record/manifest.hpp"
#include "product_schema.hpp"
#include "record_scratch.hpp"

namespace nat = flipper::naturalization;

namespace {
nat::StoredRule rule(const std::string& word) {
  nat::StoredRule r;
  r.lhs = "$Action";
  r.rhs = {word, "$Number"};
  r.semantics = "{repeat $1 times {pick item }}";
  r.author = "ana";
  r.head = word + " 3";
  r.body = {"repeat 3 times pick item"};
  r.how = "simple";
  return r;
}
}  // namespace

TEST_CASE("the manifest names the lexicon store a run starts from", "[record][lexicon]") {
  const auto dir = recordtest::scratch("lexicon-provenance");
  const std::string path = (dir / "lexicon.sqlite").string();
  const auto config = [&](const std::string& p) {
    return flipper::kernel::Config::load(std::nullopt, {"lexicon.path=" + p});
  };
  // No store yet (the run starts empty) and :memory: name nothing.
  CHECK(flipper::record::lexicon_json(config(path)).is_null());
  CHECK_FALSE(flipper::record::config_json(config(":memory:")).contains("lexicon"));
  std::string tagged_sum;
  {
    nat::LexiconStore store(path);
    store.commit_definition({0, "glorp 3", {"b"}, "ana", 1}, {rule("glorp")});
    tagged_sum = store.tag("baseline", "lead", 2).checksum;
  }
  auto lex = flipper::record::config_json(config(path)).at("lexicon");
  CHECK(lex["path"] == path);
  CHECK(lex["entry"] == 2);
  CHECK(lex["tag"] == "baseline");
  CHECK(lex["checksum"] == tagged_sum);
  {
    nat::LexiconStore store(path);
    store.commit_definition({0, "glorq 3", {"b"}, "ana", 3}, {rule("glorq")});
  }
  // Moved on from the tag: the entry and checksum say where, no tag names it.
  lex = flipper::record::lexicon_json(config(path));
  CHECK(lex["entry"] == 4);
  CHECK(lex["tag"].is_null());
  CHECK(lex["checksum"] != tagged_sum);
}
