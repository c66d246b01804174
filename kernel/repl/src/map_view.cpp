// Text map of a world object. Each cell is two characters wide so items fit as two letters.
#include <algorithm>
#include <climits>
#include <map>
#include <sstream>
#include <utility>
#include <vector>

#include "flipper/kernel/repl.hpp"

namespace flipper::kernel::repl {
namespace {

struct Pt {
  int x = 0, y = 0, z = 0;
};

Pt point_of(const Json& p) {
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

std::string item_name(const Json& item) {
  return item.value("color", std::string("?")) + " " + item.value("shape", std::string("?"));
}

std::string item_code(const Json& item) {
  std::string c = item.value("color", std::string("?")), s = item.value("shape", std::string("?"));
  return std::string{c.empty() ? '?' : c[0], s.empty() ? '?' : s[0]};
}

std::string pt_text(const Pt& p) {
  return "[" + std::to_string(p.x) + "," + std::to_string(p.y) + "]";
}

}  // namespace

std::string render_map(const Json& world) {
  const Json& robot_json = world.contains("robot") ? world["robot"] : Json::object();
  const Pt robot = point_of(robot_json);
  std::map<std::pair<int, int>, bool> walls;  // in the robot's z layer
  std::map<std::pair<int, int>, std::vector<const Json*>> items;
  int min_x = robot.x, max_x = robot.x, min_y = robot.y, max_y = robot.y;
  auto grow = [&](const Pt& p) {
    min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
  };
  if (world.contains("walls"))
    for (const auto& w : world["walls"]) {
      Pt p = point_of(w);
      if (p.z != robot.z) continue;
      walls[{p.x, p.y}] = true;
      grow(p);
    }
  if (world.contains("items"))
    for (const auto& it : world["items"]) {
      Pt p = point_of(it);
      if (p.z != robot.z) continue;
      items[{p.x, p.y}].push_back(&it);
      grow(p);
    }
  if (world.contains("bounds")) {
    Pt lo = point_of(world["bounds"].value("min", Json::array({0, 0})));
    Pt hi = point_of(world["bounds"].value("max", Json::array({0, 0})));
    min_x = lo.x, min_y = lo.y, max_x = hi.x, max_y = hi.y;
  }

  std::ostringstream out;
  for (int y = max_y; y >= min_y; --y) {
    out << (y >= 0 && y < 10 ? " " : "") << y << " ";
    for (int x = min_x; x <= max_x; ++x) {
      auto cell = items.find({x, y});
      std::size_t n = cell == items.end() ? 0 : cell->second.size();
      if (x == robot.x && y == robot.y) {
        out << (n == 0 ? "R " : "R*");
      } else if (walls.count({x, y})) {
        out << "##";
      } else if (n == 1) {
        out << item_code(*cell->second.front());
      } else if (n > 1) {
        out << (n < 10 ? std::to_string(n) : "+") << '*';
      } else {
        out << ". ";
      }
    }
    out << '\n';
  }
  out << "   ";
  for (int x = min_x; x <= max_x; ++x) {
    std::string label = std::to_string(x);
    out << (label.size() == 1 ? label + " " : label.substr(label.size() - 2));
  }
  out << "  (x)\n";

  out << "Legend: ## wall, . free, R robot, two letters = one item (colour, shape), n* = n items\n";
  std::map<std::string, std::string> codes;
  for (const auto& [at, list] : items)
    for (const Json* it : list) codes.emplace(item_code(*it), item_name(*it));
  if (!codes.empty()) {
    out << "  ";
    bool first = true;
    for (const auto& [code, name] : codes)
      out << (first ? "" : ", ") << code << " " << name, first = false;
    out << '\n';
  }
  for (const auto& [at, list] : items) {
    if (list.size() < 2 && !(at.first == robot.x && at.second == robot.y)) continue;
    out << "  " << pt_text({at.first, at.second, 0}) << ": ";
    for (std::size_t i = 0; i < list.size(); ++i) out << (i ? ", " : "") << item_name(*list[i]);
    out << '\n';
  }
  out << "Robot at " << pt_text(robot) << ", holding: ";
  const Json held = robot_json.value("holding", Json::array());
  if (held.empty()) out << "nothing";
  for (std::size_t i = 0; i < held.size(); ++i) out << (i ? ", " : "") << item_name(held[i]);
  out << '\n';
  if (world.contains("rooms") && !world["rooms"].empty()) {
    out << "Rooms:";
    for (const auto& [name, cells] : world["rooms"].items()) {
      int x0 = INT_MAX, x1 = INT_MIN, y0 = INT_MAX, y1 = INT_MIN;
      for (const auto& c : cells) {
        Pt p = point_of(c);
        x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y),
        y1 = std::max(y1, p.y);
      }
      out << ' ' << name << " (x " << x0 << ".." << x1 << ", y " << y0 << ".." << y1 << ")";
    }
    out << '\n';
  }
  return out.str();
}

}  // namespace flipper::kernel::repl
