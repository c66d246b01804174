// Top-level members of an object text found without a parse (toolkit/json/raw_members.hpp):
// exact views on hand-written texts, and the empty answers for what is not one object.
#include <catch2/catch.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "flipper/toolkit/json/raw_members.hpp"

namespace {

using flipper::toolkit::json::top_level_members;
using flipper::toolkit::json::top_level_value;

std::vector<std::string> listed(std::string_view text) {
  std::vector<std::string> out;
  for (const auto& m : top_level_members(text))
    out.push_back(std::string(m.key) + "=" + std::string(m.value));
  return out;
}

}  // namespace

TEST_CASE("members are the keys as written and the values' raw text, in order", "[json]") {
  CHECK(listed(R"({"a":1, "b" : {"c":[1,"}]"]}, "d":"x\"y","e":[{},[]],"f":null})") ==
        std::vector<std::string>{R"("a"=1)", R"("b"={"c":[1,"}]"]})", R"("d"="x\"y")",
                                 R"("e"=[{},[]])", R"("f"=null)"});
  CHECK(listed(" \t\r\n{ \"a\" :\n true } ") == std::vector<std::string>{R"("a"=true)"});
  CHECK(listed("{}").empty());
  CHECK(listed("{ }").empty());
}

TEST_CASE("what is not one object gives no members", "[json]") {
  for (const char* text : {"", "[1]", "1", R"("a")", R"({"a":)", R"({"a":1)", R"({"a" 1})",
                           R"({a:1})", R"({"a":1,})", R"({"a":[1})", R"({"a":"b)"}) {
    INFO(text);
    CHECK(top_level_members(text).empty());
  }
}

TEST_CASE("a member's value is the last one of that key, escaped keys left to a parser", "[json]") {
  CHECK(top_level_value(R"({"id":1.10,"x":2})", "id") == "1.10");
  CHECK(top_level_value(R"({"id":1,"id":"two"})", "id") == R"("two")");
  CHECK(top_level_value(R"({"idx":1})", "id").empty());
  CHECK(top_level_value(R"({"b":{"id":1}})", "id").empty());  // top level only
  CHECK(top_level_value(R"({"\u0069d":1,"id":2})", "id").empty());
  CHECK(top_level_value("not json", "id").empty());
}
