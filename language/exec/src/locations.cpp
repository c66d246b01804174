// Numbers, points, areas and collections (core-language §4.2, §4.9), evaluated against the
// current state at the moment the enclosing action runs.
#include <algorithm>
#include <cmath>
#include <string>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "interpreter.hpp"

namespace flipper::language::detail {

using sdk::Area;
using sdk::Cell;
using sdk::Kind;
using sdk::Node;
using sdk::WorldState;

namespace {
[[noreturn]] void exec_error(const std::string& what) {
  throw sdk::Error(sdk::codes::kExecution, what);
}

void add_unique(Collection& c, Area a) {
  if (std::find(c.begin(), c.end(), a) == c.end()) c.push_back(std::move(a));
}
bool has_area(const Collection& c, const Area& a) {
  return std::find(c.begin(), c.end(), a) != c.end();
}

bool lying_match_in(const Node& item, const WorldState& s, const Area& cells) {
  for (const auto& li : s.items)
    if (sdk::areas::contains(cells, li.at) && matches(item, li.item)) return true;
  return false;
}

// The cells holding an item that matches `item`, sorted and distinct: few next to the cells of
// an area (`world` has a million on a 1024^2 map), so `A containing item` intersects with them
// rather than filtering A cell by cell.
Area cells_holding(const Node& item, const WorldState& s) {
  Area out;
  for (const auto& li : s.items)
    if (matches(item, li.item)) out.push_back(li.at);
  sdk::areas::normalize(out);
  return out;
}
}  // namespace

double Interpreter::number(const Node& n) {
  switch (n.kind) {
    case Kind::Num:
      return n.number;
    case Kind::Add:
      return number(*n.kids[0]) + number(*n.kids[1]);
    case Kind::Sub:
      return number(*n.kids[0]) - number(*n.kids[1]);
    default:
      exec_error(std::string("not a number: ") + sdk::kind_name(n.kind));
  }
}

std::int32_t Interpreter::integer(const Node& n, const char* what) {
  const double v = number(n);
  if (!std::isfinite(v) || v != std::floor(v) || std::fabs(v) > 1e9)
    exec_error(std::string(what) + " " + sdk::render(std::make_shared<const Node>(n)) +
               " is not an integer");
  return static_cast<std::int32_t>(v);
}

Cell Interpreter::point(const Node& n, const WorldState& s) {
  switch (n.kind) {
    case Kind::PointXY: {
      if (n.kids.size() == 3 && geometry_.dims() == 2)
        exec_error("the point has three coordinates but the world is 2-D");
      Cell c;
      c.x = integer(*n.kids[0], "coordinate");
      c.y = integer(*n.kids[1], "coordinate");
      if (n.kids.size() == 3) c.z = integer(*n.kids[2], "coordinate");
      return c;
    }
    case Kind::Current:
      return s.robot;
    case Kind::PointVar:
      if (point_vars_.empty()) exec_error("'point' is used outside a 'foreach point' loop");
      return point_vars_.back();
    default:
      exec_error(std::string("not a point: ") + sdk::kind_name(n.kind));
  }
}

const Area& Interpreter::room(const Node& n) {
  auto it = rooms_.find(n.text);
  if (it == rooms_.end()) {
    std::string known;
    for (const auto& [name, cells] : rooms_) known += (known.empty() ? "" : ", ") + name;
    exec_error("unknown room '" + n.text + "' (this world defines " +
               (known.empty() ? std::string("no rooms") : known) + ")");
  }
  return it->second;
}

Area Interpreter::area(const Node& n, const WorldState& s) {
  switch (n.kind) {
    case Kind::World:
      return geometry_.free_cells();
    case Kind::Room:
      return room(n);
    case Kind::AreaVar:
      if (area_vars_.empty()) exec_error("'area' is used outside a 'foreach area' loop");
      return area_vars_.back();
    case Kind::PointList: {
      Area a;
      a.reserve(n.kids.size());
      for (const auto& k : n.kids) a.push_back(point(*k, s));
      sdk::areas::normalize(a);
      return a;
    }
    case Kind::Corners: {
      const Cell p = point(*n.kids[0], s), q = point(*n.kids[1], s);
      const Cell lo{std::min(p.x, q.x), std::min(p.y, q.y), std::min(p.z, q.z)};
      const Cell hi{std::max(p.x, q.x), std::max(p.y, q.y), std::max(p.z, q.z)};
      Area a;
      for (const Cell& c : geometry_.free_cells())  // already sorted
        if (c.x >= lo.x && c.x <= hi.x && c.y >= lo.y && c.y <= hi.y && c.z >= lo.z && c.z <= hi.z)
          a.push_back(c);
      return a;
    }
    case Kind::AreaOr:
      return sdk::areas::unite(area(*n.kids[0], s), area(*n.kids[1], s));
    case Kind::AreaAnd:
      return sdk::areas::intersect(area(*n.kids[0], s), area(*n.kids[1], s));
    case Kind::AreaMinus:
      return sdk::areas::subtract(area(*n.kids[0], s), area(*n.kids[1], s));
    case Kind::AreaContaining: {
      const Node& inner = *n.kids[0];
      if (inner.kind == Kind::World) {  // world = the free cells: no copy of them needed
        Area a = cells_holding(*n.kids[1], s);
        std::erase_if(a, [&](const Cell& c) { return !geometry_.is_free(c); });
        return a;
      }
      Area a = area(inner, s);
      const Area holding = cells_holding(*n.kids[1], s);
      std::erase_if(a, [&](const Cell& c) { return !sdk::areas::contains(holding, c); });
      return a;
    }
    default:
      exec_error(std::string("not an area: ") + sdk::kind_name(n.kind));
  }
}

Collection Interpreter::collection(const Node& n, const WorldState& s) {
  switch (n.kind) {
    case Kind::Rooms: {
      Collection c;
      for (const auto& [name, cells] : rooms_) add_unique(c, cells);  // by room name
      return c;
    }
    case Kind::AreaList: {
      Collection c;
      for (const auto& k : n.kids) add_unique(c, area(*k, s));
      return c;
    }
    case Kind::CollOr: {
      Collection c = collection(*n.kids[0], s);
      for (auto& a : collection(*n.kids[1], s)) add_unique(c, std::move(a));
      return c;
    }
    case Kind::CollAnd: {
      Collection c = collection(*n.kids[0], s);
      const Collection d = collection(*n.kids[1], s);
      std::erase_if(c, [&](const Area& a) { return !has_area(d, a); });
      return c;
    }
    case Kind::CollMinus: {
      Collection c = collection(*n.kids[0], s);
      const Collection d = collection(*n.kids[1], s);
      std::erase_if(c, [&](const Area& a) { return has_area(d, a); });
      return c;
    }
    case Kind::CollContaining: {
      Collection c = collection(*n.kids[0], s);
      const Node& item = *n.kids[1];
      std::erase_if(c, [&](const Area& a) { return !lying_match_in(item, s, a); });
      return c;
    }
    default:
      exec_error(std::string("not a collection: ") + sdk::kind_name(n.kind));
  }
}

bool Interpreter::condition(const Node& n, const WorldState& s) {
  switch (n.kind) {
    case Kind::CondAnd:
      return condition(*n.kids[0], s) && condition(*n.kids[1], s);
    case Kind::CondOr:
      return condition(*n.kids[0], s) || condition(*n.kids[1], s);
    case Kind::CondNot:
      return !condition(*n.kids[0], s);
    case Kind::ItemAtPoint: {
      const Cell p = point(*n.kids[1], s);
      for (const auto& li : s.items)
        if (li.at == p && matches(*n.kids[0], li.item)) return true;
      return false;
    }
    case Kind::ItemAtArea:
      if (n.kids[1]->kind == Kind::World) {  // as in AreaContaining: no copy of the free cells
        for (const auto& li : s.items)
          if (geometry_.is_free(li.at) && matches(*n.kids[0], li.item)) return true;
        return false;
      }
      return lying_match_in(*n.kids[0], s, area(*n.kids[1], s));
    case Kind::RobotHas:
      for (const auto& h : s.held)
        if (matches(*n.kids[0], h)) return true;
      return false;
    case Kind::RobotAtPoint:
      return s.robot == point(*n.kids[0], s);
    case Kind::RobotAtArea:
      return sdk::areas::contains(area(*n.kids[0], s), s.robot);
    case Kind::Possible:
      return trial(*n.kids[0], s, nullptr);
    default:
      exec_error(std::string("not a condition: ") + sdk::kind_name(n.kind));
  }
}

}  // namespace flipper::language::detail
