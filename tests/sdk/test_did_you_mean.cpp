// sdk::did_you_mean: a hint for typos, never for unrelated words or punctuation (the words new
// users try first got '+' and 'if' before).
#include <catch2/catch.hpp>

#include "flipper/sdk/param_check.hpp"

using flipper::sdk::did_you_mean;

TEST_CASE("did you mean: typos within one edit per three letters, transpositions count one") {
  const std::vector<std::string> words = {"visit", "move",  "pick", "+",  "if",     "{",
                                          ";",     "room1", "k",    "up", "session"};
  CHECK(did_you_mean("vist", words) == " (did you mean 'visit'?)");
  CHECK(did_you_mean("mvoe", words) == " (did you mean 'move'?)");  // one transposition
  CHECK(did_you_mean("pik", words) == " (did you mean 'pick'?)");
  CHECK(did_you_mean("sesion", words) == " (did you mean 'session'?)");
  CHECK(did_you_mean("kk", words) == " (did you mean 'k'?)");  // keeps its first letter
  // Not typos: nothing rather than nonsense.
  CHECK(did_you_mean("go", words).empty());   // was '+'
  CHECK(did_you_mean("zig", words).empty());  // was 'if'
  CHECK(did_you_mean("r", words).empty());    // was '+'
  CHECK(did_you_mean("uo", words) == " (did you mean 'up'?)");
  CHECK(did_you_mean("pu", words).empty());     // two letters: "up" is one transposition away, but
                                                // a two-letter word must keep its first letter
  CHECK(did_you_mean("visit", words).empty());  // a known word needs no hint
  // Punctuation is offered for punctuation only.
  CHECK(did_you_mean("{{", {"{", "move"}) == " (did you mean '{'?)");
}

TEST_CASE("did you mean: the distance limit at N and N+1") {
  // Six letters allow two edits, five letters one.
  CHECK(did_you_mean("abcdef", {"abcdxx"}) == " (did you mean 'abcdxx'?)");
  CHECK(did_you_mean("abcdef", {"abcxxx"}).empty());
  CHECK(did_you_mean("abcde", {"abcdx"}) == " (did you mean 'abcdx'?)");
  CHECK(did_you_mean("abcde", {"abcxx"}).empty());
  // The closest wins; the first of equals.
  CHECK(did_you_mean("abcdef", {"abcdxx", "abcdex", "abcdey"}) == " (did you mean 'abcdex'?)");
}
