// --set text values reach the commands verbatim: an in-memory lexicon and an empty preload
// without YAML quoting, and a quoted value unquoted.
#include "cli_test_support.hpp"

using namespace flipper::clitest;

TEST_CASE("set lexicon.path=:memory: and an empty preload work unquoted", "[cli][set]") {
  const Run check = run_flipper("config check --set lexicon.path=:memory: --set lexicon.preload=");
  INFO(check.out);
  REQUIRE(check.status == 0);
  CHECK(contains(check.out, ":memory:"));

  // A session on :memory: writes no file and still learns within the process.
  const std::string script = write_file("memory.jsonl", R"({"op":"user","name":"ana"}
{"op":"define","head":"pick 3 items","body":["repeat 3 times pick item"]}
{"op":"query","text":"drop 2 items"}
)");
  const Run s =
      run_flipper("session --set lexicon.path=:memory: --set lexicon.preload= " + script, false);
  INFO(s.out);
  REQUIRE(s.status == 0);
  CHECK(contains(s.out, R"("status":"induced")"));
  CHECK_FALSE(std::filesystem::exists(":memory:"));

  const Run quoted = run_flipper("config check --set 'lexicon.path=\":memory:\"'");
  CHECK(quoted.status == 0);
  const Run odd = run_flipper("config check --set 'lexicon.path=a: b.sqlite'");
  INFO(odd.out);
  CHECK(odd.status == 0);
  CHECK(contains(odd.out, "a: b.sqlite"));
}
