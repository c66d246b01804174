// Lexer and number tokens (core-language §2).
#include <catch2/catch.hpp>

#include "flipper/sdk/canonical.hpp"

using flipper::sdk::number_value;
using flipper::sdk::tokenize;
using V = std::vector<std::string>;

TEST_CASE("tokenize lower-cases and splits on whitespace", "[lexer]") {
  CHECK(tokenize("Visit  World\tcontaining ITEM") == V{"visit", "world", "containing", "item"});
  CHECK(tokenize("") == V{});
  CHECK(tokenize("   ") == V{});
}

TEST_CASE("tokenize separates punctuation characters", "[lexer]") {
  CHECK(tokenize("[1,2]") == V{"[", "1", ",", "2", "]"});
  CHECK(tokenize("{move up};move") == V{"{", "move", "up", "}", ";", "move"});
  CHECK(tokenize("a?b'c\"d") == V{"a", "?", "b", "'", "c", "\"", "d"});
  CHECK(tokenize("2+1=3") == V{"2", "+", "1", "=", "3"});
  CHECK(tokenize("a<=b>=c<d>e") == V{"a", "<=", "b", ">=", "c", "<", "d", ">", "e"});
}

TEST_CASE("tokenize hyphen rules", "[lexer]") {
  CHECK(tokenize("pick-up") == V{"pick", "up"});
  CHECK(tokenize("-3") == V{"-3"});
  CHECK(tokenize("3-1") == V{"3-1"});
  CHECK(tokenize("3 - 1") == V{"3", "-", "1"});
  CHECK(tokenize("[-1,-2]") == V{"[", "-1", ",", "-2", "]"});
  CHECK(tokenize("x -a") == V{"x", "a"});
}

TEST_CASE("tokenize period rule", "[lexer]") {
  CHECK(tokenize("move up.") == V{"move", "up", "."});
  CHECK(tokenize("2.5") == V{"2.5"});
  CHECK(tokenize(".start") == V{".", "start"});
  CHECK(tokenize("a . b") == V{"a", ".", "b"});
  CHECK(tokenize("a.b") == V{"a.b"});
  CHECK(tokenize("up. left") == V{"up", ".", "left"});
}

TEST_CASE("number_value accepts decimals and number words in range", "[lexer]") {
  CHECK(number_value("3") == 3.0);
  CHECK(number_value("-1") == -1.0);
  CHECK(number_value("2.5") == 2.5);
  CHECK(number_value("99") == 99.0);
  CHECK(number_value("-99") == -99.0);
  CHECK(number_value("zero") == 0.0);
  CHECK(number_value("ten") == 10.0);
  CHECK(number_value("three") == 3.0);
  CHECK(tokenize("Three") == V{"three"});
  CHECK(number_value(tokenize("Three")[0]) == 3.0);
}

TEST_CASE("number_value rejects other forms", "[lexer]") {
  for (const char* t : {"100", "-100", "99.5", "1e1", "2d", "0x1p1", "NaN", "nan", "inf", "3-1",
                        "-", "1.", ".5", "+3", "eleven", "", "3a", "--3"})
    CHECK_FALSE(number_value(t).has_value());
}
