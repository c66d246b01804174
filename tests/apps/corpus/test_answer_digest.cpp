// The text a study's recording hashes for an answer (flipper/corpus/answer_digest.hpp,
// docs/studio.md §7): every `,"ms":NUMBER` member removed, nothing else, so that two runs of the
// same exchange hash alike whatever their timings. Expected texts written by hand.
#include <catch2/catch.hpp>
#include <string>

#include "flipper/corpus/answer_digest.hpp"

using flipper::corpus::answer_for_digest;

TEST_CASE("answer_for_digest drops every ms member and keeps everything else", "[corpus]") {
  CHECK(answer_for_digest(R"({"ok":true,"ms":12})") == R"({"ok":true})");
  CHECK(answer_for_digest(R"({"ok":true,"ms":0.25,"op":"query"})") ==
        R"({"ok":true,"op":"query"})");
  // Every occurrence, nested ones too, and the number forms JSON allows.
  CHECK(answer_for_digest(R"({"a":{"b":1,"ms":-3},"ms":1.5e3,"c":[{"x":0,"ms":7E-2}]})") ==
        R"({"a":{"b":1},"c":[{"x":0}]})");
  // No ms member: the text unchanged.
  CHECK(answer_for_digest(R"({"ok":false,"error":{"code":"bad_json"}})") ==
        R"({"ok":false,"error":{"code":"bad_json"}})");
  CHECK(answer_for_digest("").empty());
}

TEST_CASE("answer_for_digest leaves ms that is not a number member alone", "[corpus]") {
  // Inside a JSON string the quotes are escaped, so the pattern does not occur there.
  CHECK(answer_for_digest(R"({"text":"a \",\"ms\":5 b","ms":5})") ==
        R"({"text":"a \",\"ms\":5 b"})");
  // A value that is not a number is kept, with the key.
  CHECK(answer_for_digest(R"({"x":1,"ms":"fast"})") == R"({"x":1,"ms":"fast"})");
  CHECK(answer_for_digest(R"({"x":1,"ms":null})") == R"({"x":1,"ms":null})");
  // The key at the very end, with no value after it.
  CHECK(answer_for_digest(R"({"x":1,"ms":)") == R"({"x":1,"ms":)");
  // Only the member named exactly ms: "rms" and "ms2" stay.
  CHECK(answer_for_digest(R"({"rms":3,"ms2":4})") == R"({"rms":3,"ms2":4})");
}
