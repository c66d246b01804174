// apps/svg on its own: the element writer's exact output, the protocol's cell forms, and the world
// picture of a 3 x 2 world whose pixel positions are computed by hand (28 px cells; the left
// margin 36 px, the top 44 px; cell (x, y) has its top-left corner at (36 + 28 (x - min_x),
// 44 + 28 (max_y - y))). `flipper run --svg` through the command line is tests/apps/cli/test_svg.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "flipper/svg/svg.hpp"

namespace svg = flipper::svg;
using nlohmann::json;

namespace {

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

bool contains(const std::string& text, const std::string& what) {
  return text.find(what) != std::string::npos;
}

}  // namespace

TEST_CASE("escape and num", "[svg]") {
  CHECK(svg::escape(R"(a<b>&"c' d)") == "a&lt;b&gt;&amp;&quot;c' d");
  CHECK(svg::escape("").empty());
  CHECK(svg::num(3) == "3.0");
  CHECK(svg::num(12.5) == "12.5");
  CHECK(svg::num(1.26) == "1.3");
  CHECK(svg::num(-7.04) == "-7.0");
}

TEST_CASE("the writer's document, element by element", "[svg]") {
  svg::Writer w(100, 50, 12);
  w.rect(1, 2, 3, 4, "red");
  w.line(0, 0, 10, 5, "#ddd", 0.5);
  w.circle(5, 6, 2, "none", "blue");
  w.polyline({{1, 1}, {2.5, 3}}, "green", 3);
  w.text(5, 6, "a<b", "middle");
  w.text(7, 8, "t", "end", 9, "#777");
  w.raw("<g/>");
  CHECK(w.str() ==
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100.0\" height=\"50.0\" "
        "viewBox=\"0 0 100.0 50.0\" font-family=\"sans-serif\" font-size=\"12\">\n"
        "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
        "<rect x=\"1.0\" y=\"2.0\" width=\"3.0\" height=\"4.0\" fill=\"red\" stroke=\"none\"/>\n"
        "<line x1=\"0.0\" y1=\"0.0\" x2=\"10.0\" y2=\"5.0\" stroke=\"#ddd\" "
        "stroke-width=\"0.5\"/>\n"
        "<circle cx=\"5.0\" cy=\"6.0\" r=\"2.0\" fill=\"none\" stroke=\"blue\"/>\n"
        "<polyline fill=\"none\" stroke=\"green\" stroke-width=\"3.0\" stroke-linejoin=\"round\" "
        "points=\"1.0,1.0 2.5,3.0 \"/>\n"
        "<text x=\"5.0\" y=\"6.0\" text-anchor=\"middle\">a&lt;b</text>\n"
        "<text x=\"7.0\" y=\"8.0\" text-anchor=\"end\" font-size=\"9\" fill=\"#777\">t</text>\n"
        "<g/>\n"
        "</svg>\n");
}

TEST_CASE("point_of reads every cell form of the protocol", "[svg]") {
  const auto same = [](const svg::Pt& p, int x, int y, int z) {
    return p.x == x && p.y == y && p.z == z;
  };
  CHECK(same(svg::point_of(json::array({1, 2})), 1, 2, 0));
  CHECK(same(svg::point_of(json::array({1, 2, 3})), 1, 2, 3));
  CHECK(same(svg::point_of(json{{"x", 4}, {"z", 5}}), 4, 0, 5));
  // Anything else is the origin.
  CHECK(same(svg::point_of(json::array({7})), 0, 0, 0));
  CHECK(same(svg::point_of(json("junk")), 0, 0, 0));
}

TEST_CASE("the world picture of a 3 x 2 world, with and without a plan", "[svg]") {
  const json world = json::parse(R"({
    "bounds": {"min": [0, 0], "max": [2, 1]},
    "walls": [[1, 1]],
    "rooms": {"r1": [[0, 0], [0, 1]]},
    "robot": [0, 0],
    "items": [{"x": 2, "y": 0, "color": "red", "shape": "circle"}]
  })");
  const std::string plain = svg::world_picture(world, nullptr, "a <title>");
  // 36 + 3 cells + 16 wide; 44 + 2 cells + 24 + the legend's 58 high.
  CHECK(plain.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"136.0\" height=\"182.0\"",
                    0) == 0);
  CHECK(contains(plain, ">a &lt;title&gt;</text>"));
  // 2-D: no floor line.
  CHECK_FALSE(contains(plain, "floor z="));
  // The room's two cells tinted, its label in its top-left cell (0, 1).
  CHECK(contains(plain, R"(<rect x="36.0" y="72.0" width="28.0" height="28.0" fill="#e8f0fb")"));
  CHECK(contains(plain, R"(<rect x="36.0" y="44.0" width="28.0" height="28.0" fill="#e8f0fb")"));
  CHECK(contains(plain, R"(<text x="38.0" y="53.0" text-anchor="start" font-size="8" )"
                        R"(fill="#666">r1</text>)"));
  // The wall at (1, 1), and the legend's wall square: two dark squares in all.
  CHECK(contains(plain, R"(<rect x="64.0" y="44.0" width="28.0" height="28.0" fill="#555")"));
  CHECK(count(plain, R"(fill="#555" stroke=)") == 2);
  // The red circle at (2, 0), the robot at (0, 0).
  CHECK(contains(plain, R"(<circle cx="106.0" cy="86.0" r="8.0" fill="red" stroke="#333"/>)"));
  CHECK(contains(plain, R"(<circle cx="50.0" cy="86.0" r="9.0" fill="white" stroke="#1d3557"/>)"));
  CHECK_FALSE(contains(plain, "<polyline"));
  CHECK(contains(plain, ">x right, y up</text>"));

  // The plan: right to (1, 0), then a pick there.
  const json trace = json::parse(R"([{"act": "move", "to": [1, 0]},
                                     {"act": "pick", "at": [1, 0]}])");
  const std::string planned = svg::world_picture(world, &trace, "plan");
  CHECK(contains(planned, R"(points="50.0,86.0 78.0,86.0 ")"));
  CHECK(contains(planned, R"(<circle cx="78.0" cy="86.0" r="7.0" fill="none" stroke="#e4572e"/>)"));
  CHECK(contains(planned, R"(<text x="89.0" y="82.0" text-anchor="end" font-size="10" )"
                          R"(fill="#1b7f3b">P</text>)"));
  CHECK(contains(planned, ">1 moves, 1 picks, 0 drops; x right, y up</text>"));
}

TEST_CASE("a 3-D world shows the robot's floor only", "[svg]") {
  const json world = json::parse(R"({
    "bounds": {"min": [0, 0, 0], "max": [1, 0, 1]},
    "walls": [[0, 0, 0], [1, 0, 1]],
    "robot": [0, 0, 1],
    "items": [{"x": 1, "y": 0, "z": 0, "color": "blue", "shape": "square"}]
  })");
  const std::string pic = svg::world_picture(world, nullptr, "floors");
  CHECK(contains(pic, ">floor z=1</text>"));
  // Floor 1 has the wall at (1, 0) and not the one at (0, 0); the item lies on floor 0.
  CHECK(contains(pic, R"(<rect x="64.0" y="44.0" width="28.0" height="28.0" fill="#555")"));
  CHECK_FALSE(contains(pic, R"(<rect x="36.0" y="44.0" width="28.0" height="28.0" fill="#555")"));
  CHECK_FALSE(contains(pic, R"(fill="blue")"));
}
