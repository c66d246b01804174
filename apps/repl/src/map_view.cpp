// Text map of a world object. Each cell is two characters wide so items fit as two letters.
// Optionally a trace is drawn on it (a candidate's path, or the path just taken).
#include <algorithm>
#include <climits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "flipper/repl/repl.hpp"
#include "flipper/svg/svg.hpp"

namespace flipper::repl {
namespace {

using svg::point_of;
using svg::Pt;

std::string item_name(const kernel::Json& item) {
  return item.value("color", std::string("?")) + " " + item.value("shape", std::string("?"));
}

std::string item_code(const kernel::Json& item) {
  std::string c = item.value("color", std::string("?")), s = item.value("shape", std::string("?"));
  return std::string{c.empty() ? '?' : c[0], s.empty() ? '?' : s[0]};
}

std::string pt_text(const Pt& p, bool three_d) {
  return "[" + std::to_string(p.x) + "," + std::to_string(p.y) +
         (three_d ? "," + std::to_string(p.z) : "") + "]";
}

bool is_3d(const kernel::Json& world) {
  if (world.contains("bounds")) {
    const kernel::Json& lo = world["bounds"].value("min", kernel::Json::array());
    if (lo.is_array() && lo.size() >= 3) return true;
  }
  const kernel::Json& r = world.contains("robot") ? world["robot"] : kernel::Json::object();
  return r.is_object() && r.contains("z");
}

// The x axis: one label per column when every label is one digit, else a label every 5th
// column (full numbers never overlap, so it reads the same at any width).
std::string x_axis(int min_x, int max_x) {
  const bool every = min_x >= 0 && max_x <= 9;
  std::string row(3 + 2 * static_cast<std::size_t>(max_x - min_x + 1), ' ');
  std::size_t free_from = 0;  // a label starts only after the previous one and a space
  for (int x = min_x; x <= max_x; ++x) {
    if (!every && x % 5 != 0) continue;
    const std::size_t at = 3 + 2 * static_cast<std::size_t>(x - min_x);
    if (at < free_from) continue;
    const std::string label = std::to_string(x);
    if (row.size() < at + label.size()) row.resize(at + label.size(), ' ');
    row.replace(at, label.size(), label);
    free_from = at + label.size() + 1;
  }
  return row + "  (x)";
}

// `lead` then the parts separated by ", ", wrapped before 80 columns (continuation indented).
std::string wrapped(const std::string& lead, const std::vector<std::string>& parts) {
  std::string out = lead, line = lead;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string piece = parts[i] + (i + 1 < parts.size() ? "," : "");
    if (line.size() + 1 + piece.size() > 79 && line.size() > 4) {
      out += "\n   ";
      line = "   ";
    }
    out += " " + piece;
    line += " " + piece;
  }
  return out + "\n";
}

}  // namespace

std::string render_map(const kernel::Json& world, const MapOptions& options) {
  const kernel::Json& robot_json =
      world.contains("robot") ? world["robot"] : kernel::Json::object();
  const Pt robot = point_of(robot_json);
  const bool three_d = is_3d(world);
  const int floor = options.floor.value_or(robot.z);
  std::set<std::pair<int, int>> walls;  // in the shown floor
  std::map<std::pair<int, int>, std::vector<const kernel::Json*>> items;
  std::map<int, std::vector<const kernel::Json*>> other_floors;
  int min_x = robot.x, max_x = robot.x, min_y = robot.y, max_y = robot.y;
  int min_z = robot.z, max_z = robot.z;
  auto grow = [&](const Pt& p) {
    min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
  };
  if (world.contains("walls"))
    for (const auto& w : world["walls"]) {
      Pt p = point_of(w);
      if (p.z != floor) continue;
      walls.insert({p.x, p.y});
      grow(p);
    }
  if (world.contains("boxes"))  // 3-D worlds: walls as boxes of cells
    for (const auto& b : world["boxes"]) {
      const Pt lo = point_of(b.value("min", kernel::Json::array())),
               hi = point_of(b.value("max", kernel::Json::array()));
      if (floor < lo.z || floor > hi.z) continue;
      for (int x = lo.x; x <= hi.x; ++x)
        for (int y = lo.y; y <= hi.y; ++y) walls.insert({x, y});
      grow(lo), grow(hi);
    }
  if (world.contains("items"))
    for (const auto& it : world["items"]) {
      Pt p = point_of(it);
      if (p.z != floor) {
        other_floors[p.z].push_back(&it);
        continue;
      }
      items[{p.x, p.y}].push_back(&it);
      grow(p);
    }
  if (world.contains("bounds")) {
    Pt lo = point_of(world["bounds"].value("min", kernel::Json::array({0, 0})));
    Pt hi = point_of(world["bounds"].value("max", kernel::Json::array({0, 0})));
    min_x = lo.x, min_y = lo.y, max_x = hi.x, max_y = hi.y, min_z = lo.z, max_z = hi.z;
  }

  // The trace on this floor: path cells, the end cell, picks and drops.
  std::set<std::pair<int, int>> path, picks, drops;
  std::pair<int, int> end{INT_MIN, INT_MIN};  // none yet
  if (options.trace != nullptr)
    for (const auto& s : *options.trace) {
      const std::string act = s.value("act", std::string());
      const Pt p =
          point_of(act == "move" ? s.value("to", kernel::Json()) : s.value("at", kernel::Json()));
      if (p.z != floor) {
        if (act == "move") end = {INT_MIN, INT_MIN};
        continue;
      }
      if (act == "move") {
        path.insert({p.x, p.y});
        end = {p.x, p.y};
      } else {
        (act == "pick" ? picks : drops).insert({p.x, p.y});
      }
    }

  std::ostringstream out;
  if (three_d)
    out << "Floor z=" << floor << " (floors " << min_z << ".." << max_z
        << (max_z > min_z ? "; :floor N shows another" : "") << ")\n";
  const bool robot_here = robot.z == floor;
  for (int y = max_y; y >= min_y; --y) {
    out << (y >= 0 && y < 10 ? " " : "") << y << " ";
    for (int x = min_x; x <= max_x; ++x) {
      const std::pair<int, int> at{x, y};
      auto cell = items.find(at);
      std::size_t n = cell == items.end() ? 0 : cell->second.size();
      if (robot_here && x == robot.x && y == robot.y) {
        out << (n == 0 ? "R " : "R*");
      } else if (walls.count(at)) {
        out << "##";
      } else if (end == at) {
        out << (n == 0 ? "E " : "E*");  // the end of the path wins over the items there
      } else if (picks.count(at) || drops.count(at)) {
        out << (picks.count(at) && drops.count(at) ? "PD" : picks.count(at) ? "P " : "D ");
      } else if (n == 1) {
        out << item_code(*cell->second.front());
      } else if (n > 1) {
        out << (n < 10 ? std::to_string(n) : "+") << '*';
      } else if (path.count(at)) {
        out << "o ";
      } else {
        out << ". ";
      }
    }
    out << '\n';
  }
  out << x_axis(min_x, max_x) << '\n';
  if (!options.legend) return out.str();

  std::vector<std::string> legend = {"## wall", ". free", "R robot (R* on items)",
                                     "two letters one item (colour, shape)",
                                     "n* a stack of n items (listed below)"};
  if (options.trace != nullptr)
    legend.insert(legend.end(), {"o path", "E end (E* on items)", "P pick", "D drop"});
  legend.push_back("y grows upwards");
  out << wrapped("Legend:", legend);
  std::map<std::string, std::string> codes;
  for (const auto& [at, list] : items)
    for (const kernel::Json* it : list) codes.emplace(item_code(*it), item_name(*it));
  if (!codes.empty()) {
    std::vector<std::string> parts;
    parts.reserve(codes.size());
    for (const auto& [code, name] : codes) parts.push_back(code + " " + name);
    out << wrapped(" ", parts);
  }
  for (const auto& [at, list] : items) {
    if (list.size() < 2 && !(robot_here && at.first == robot.x && at.second == robot.y)) continue;
    out << "  " << pt_text({at.first, at.second, floor}, three_d) << ": ";
    for (std::size_t i = 0; i < list.size(); ++i) out << (i ? ", " : "") << item_name(*list[i]);
    out << '\n';
  }
  for (const auto& [z, list] : other_floors) {
    std::vector<std::string> parts;
    for (const kernel::Json* it : list)
      parts.push_back(item_name(*it) + " at " + pt_text(point_of(*it), true));
    out << wrapped("  floor z=" + std::to_string(z) + ":", parts);
  }
  out << "Robot at " << pt_text(robot, three_d) << ", holding: ";
  const kernel::Json held = robot_json.value("holding", kernel::Json::array());
  if (held.empty()) out << "nothing";
  for (std::size_t i = 0; i < held.size(); ++i) out << (i ? ", " : "") << item_name(held[i]);
  out << '\n';
  if (world.contains("rooms") && !world["rooms"].empty()) {
    std::vector<std::string> parts;
    for (const auto& [name, cells] : world["rooms"].items()) {
      int x0 = INT_MAX, x1 = INT_MIN, y0 = INT_MAX, y1 = INT_MIN, z0 = INT_MAX, z1 = INT_MIN;
      for (const auto& c : cells) {
        Pt p = point_of(c);
        x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y),
        y1 = std::max(y1, p.y), z0 = std::min(z0, p.z), z1 = std::max(z1, p.z);
      }
      std::string room = name + " (x " + std::to_string(x0) + ".." + std::to_string(x1) + ", y " +
                         std::to_string(y0) + ".." + std::to_string(y1);
      if (three_d)
        room += ", z " + std::to_string(z0) + (z1 != z0 ? ".." + std::to_string(z1) : "");
      parts.push_back(room + ")");
    }
    out << wrapped("Rooms (areas you can name, e.g. `visit room1`):", parts);
  }
  return out.str();
}

}  // namespace flipper::repl
