// The world and a plan as an SVG picture (flipper run --svg, repl :save).
#include <algorithm>
#include <climits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "flipper/svg/svg.hpp"

namespace flipper::svg {

Pt point_of(const nlohmann::json& p) {
  Pt out;
  if (p.is_array() && p.size() >= 2) {
    out.x = p[0].get<int>();
    out.y = p[1].get<int>();
    if (p.size() >= 3) out.z = p[2].get<int>();
  } else if (p.is_object()) {
    out.x = p.value("x", 0);
    out.y = p.value("y", 0);
    out.z = p.value("z", 0);
  }
  return out;
}

namespace {

using Json = nlohmann::json;

// CSS colours for the grammar's colour words; anything else grey.
std::string css_color(const std::string& c) {
  static const std::set<std::string> known = {"black", "blue",   "gray", "green", "orange",
                                              "pink",  "purple", "red",  "yellow"};
  if (c == "grey") return "gray";
  return known.count(c) ? c : "#999";
}

const char* kRoomTints[] = {"#e8f0fb", "#fbeee6", "#e9f5ea", "#f8e7e8", "#efeaf6", "#f4efe6"};
constexpr double kCell = 28, kLeft = 36, kTop = 44, kLegend = 58;

}  // namespace

std::string world_picture(const Json& world, const Json* trace, const std::string& title) {
  const Json robot_json = world.value("robot", Json::object());
  const Pt robot = point_of(robot_json);
  int floor = robot.z;
  int min_x = robot.x, max_x = robot.x, min_y = robot.y, max_y = robot.y;
  if (world.contains("bounds")) {
    const Pt lo = point_of(world["bounds"].value("min", Json::array({0, 0})));
    const Pt hi = point_of(world["bounds"].value("max", Json::array({0, 0})));
    min_x = lo.x, min_y = lo.y, max_x = hi.x, max_y = hi.y;
  }
  std::set<std::pair<int, int>> walls;
  const Json wall_points = world.value("walls", Json::array());
  const Json boxes = world.value("boxes", Json::array());
  const Json all_items = world.value("items", Json::array());
  for (const auto& w : wall_points) {
    const Pt p = point_of(w);
    if (p.z != floor) continue;
    walls.insert({p.x, p.y});
    min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
  }
  for (const auto& b : boxes) {
    const Pt lo = point_of(b.value("min", Json::array())),
             hi = point_of(b.value("max", Json::array()));
    if (floor < lo.z || floor > hi.z) continue;
    for (int x = lo.x; x <= hi.x; ++x)
      for (int y = lo.y; y <= hi.y; ++y) walls.insert({x, y});
  }
  const double width = kLeft + kCell * (max_x - min_x + 1) + 16;
  const double height = kTop + kCell * (max_y - min_y + 1) + 24 + kLegend;
  const auto px = [&](int x) { return kLeft + kCell * (x - min_x); };
  const auto py = [&](int y) { return kTop + kCell * (max_y - y); };
  Writer w(width, height, 11);
  w.text(width / 2, 22, title, "middle", 14);
  if (world.contains("bounds") && point_of(world["bounds"].value("min", Json::array())).z !=
                                      point_of(world["bounds"].value("max", Json::array())).z)
    w.text(width / 2, 36, "floor z=" + std::to_string(floor), "middle", 11, "#555");

  // Rooms (tinted cells, a label in the top-left cell), then walls and the grid.
  int tint = 0;
  const Json rooms = world.value("rooms", Json::object());
  for (const auto& [name, cells] : rooms.items()) {
    int lx = INT_MAX, ly = INT_MIN;
    bool any = false;
    for (const auto& c : cells) {
      const Pt p = point_of(c);
      if (p.z != floor) continue;
      any = true;
      w.rect(px(p.x), py(p.y), kCell, kCell, kRoomTints[tint % 6]);
      if (p.y > ly || (p.y == ly && p.x < lx)) lx = p.x, ly = p.y;
    }
    if (any) w.text(px(lx) + 2, py(ly) + 9, name, "start", 8, "#666");
    ++tint;
  }
  for (int x = min_x; x <= max_x; ++x)
    for (int y = min_y; y <= max_y; ++y)
      if (walls.count({x, y})) w.rect(px(x), py(y), kCell, kCell, "#555");
  for (int x = min_x; x <= max_x + 1; ++x)
    w.line(px(x), py(max_y), px(x), py(min_y - 1), "#ddd", 0.5);
  for (int y = min_y - 1; y <= max_y; ++y)
    w.line(px(min_x), py(y) + kCell, px(max_x + 1), py(y) + kCell, "#ddd", 0.5);
  for (int x = min_x; x <= max_x; ++x)
    w.text(px(x) + kCell / 2, py(min_y - 1) + 12, std::to_string(x), "middle", 9, "#777");
  for (int y = min_y; y <= max_y; ++y)
    w.text(kLeft - 4, py(y) + kCell / 2 + 3, std::to_string(y), "end", 9, "#777");

  // Items: up to four per cell as small coloured shapes, with a count when there are more.
  std::map<std::pair<int, int>, std::vector<const Json*>> items;
  for (const auto& it : all_items) {
    const Pt p = point_of(it);
    if (p.z == floor) items[{p.x, p.y}].push_back(&it);
  }
  for (const auto& [at, list] : items) {
    const double s = list.size() == 1 ? 16 : 10;
    for (std::size_t i = 0; i < list.size() && i < 4; ++i) {
      const double cx = px(at.first) + (list.size() == 1 ? kCell / 2 : (i % 2 ? 20.0 : 8.0));
      const double cy = py(at.second) + (list.size() == 1 ? kCell / 2 : (i / 2 ? 20.0 : 8.0));
      const std::string fill = css_color(list[i]->value("color", std::string()));
      const std::string shape = list[i]->value("shape", std::string());
      if (shape == "circle") {
        w.circle(cx, cy, s / 2, fill, "#333");
      } else if (shape == "triangle") {
        w.raw("<polygon points=\"" + num(cx) + "," + num(cy - s / 2) + " " + num(cx - s / 2) + "," +
              num(cy + s / 2) + " " + num(cx + s / 2) + "," + num(cy + s / 2) + "\" fill=\"" +
              fill + "\" stroke=\"#333\"/>");
      } else {
        w.rect(cx - s / 2, cy - s / 2, s, s, fill, "#333");
      }
    }
    if (list.size() > 4)
      w.text(px(at.first) + kCell - 2, py(at.second) + kCell - 2, std::to_string(list.size()),
             "end", 9);
  }

  // The plan: a line from the robot through every cell entered on this floor, the end ringed,
  // P/D where items were picked and dropped.
  std::size_t moves = 0, picks = 0, drops = 0;
  if (trace != nullptr) {
    std::vector<std::pair<double, double>> path = {
        {px(robot.x) + kCell / 2, py(robot.y) + kCell / 2}};
    for (const auto& s : *trace) {
      const std::string act = s.value("act", std::string());
      const Pt p = point_of(act == "move" ? s.value("to", Json()) : s.value("at", Json()));
      if (act == "move") ++moves;
      if (p.z != floor) continue;
      if (act == "move") {
        path.emplace_back(px(p.x) + kCell / 2, py(p.y) + kCell / 2);
      } else {
        const bool pick = act == "pick";
        (pick ? picks : drops)++;
        w.text(px(p.x) + kCell - 3, py(p.y) + 10, pick ? "P" : "D", "end", 10,
               pick ? "#1b7f3b" : "#a4161a");
      }
    }
    if (path.size() > 1) {
      w.polyline(path, "#e4572e", 3);
      w.circle(path.back().first, path.back().second, 7, "none", "#e4572e");
    }
  }
  if (robot.z == floor) {
    w.circle(px(robot.x) + kCell / 2, py(robot.y) + kCell / 2, 9, "white", "#1d3557");
    w.text(px(robot.x) + kCell / 2, py(robot.y) + kCell / 2 + 4, "R", "middle", 11, "#1d3557");
  }

  // Legend.
  const double ly = kTop + kCell * (max_y - min_y + 1) + 34;
  w.rect(kLeft, ly - 9, 10, 10, "#555");
  w.text(kLeft + 14, ly, "wall", "start", 10);
  w.circle(kLeft + 58, ly - 4, 6, "white", "#1d3557");
  w.text(kLeft + 68, ly, "robot (start)", "start", 10);
  if (trace != nullptr) {
    w.line(kLeft + 140, ly - 4, kLeft + 160, ly - 4, "#e4572e", 3);
    w.text(kLeft + 164, ly, "path, end ringed; P pick, D drop", "start", 10);
    w.text(kLeft, ly + 16,
           std::to_string(moves) + " moves, " + std::to_string(picks) + " picks, " +
               std::to_string(drops) + " drops; x right, y up",
           "start", 10, "#555");
  } else {
    w.text(kLeft, ly + 16, "x right, y up", "start", 10, "#555");
  }
  return w.str();
}

}  // namespace flipper::svg
