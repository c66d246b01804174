// Accepting the second reading of an ambiguous utterance moves it to rank 0 (naturalization §3).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "session_fixture.hpp"

using flipper::kernel::Json;
using flipper::testsupport::ask;

namespace {

int rank_of(const Json& answer, const std::string& formula) {
  const Json& c = answer["candidates"];
  for (std::size_t i = 0; i < c.size(); ++i)
    if (c[i]["formula"] == formula) return static_cast<int>(i);
  return -1;
}

}  // namespace

TEST_CASE("the ranking learns from accepts", "[session][learning]") {
  auto s = flipper::testsupport::bare_session();
  const std::string text = R"({"op":"query","text":"visit room1 or room2 containing item","k":5})";
  Json first = ask(*s, text);
  REQUIRE(first["ok"] == true);
  REQUIRE(first["candidates"].size() >= 2);
  const std::string target = first["candidates"][1]["formula"].get<std::string>();
  const double p_before = first["candidates"][1]["prob"].get<double>();

  Json answer = first;
  int accepts = 0;
  while (rank_of(answer, target) != 0 && accepts < 10) {
    int r = rank_of(answer, target);
    REQUIRE(r > 0);
    Json a = ask(*s, R"({"op":"accept","rank":)" + std::to_string(r) + "}");
    REQUIRE(a["ok"] == true);
    ++accepts;
    answer = ask(*s, text);
  }
  INFO("accepts: " << accepts);
  CHECK(rank_of(answer, target) == 0);
  CHECK(answer["candidates"][0]["prob"].get<double>() > p_before);
  CHECK(accepts >= 1);
}
