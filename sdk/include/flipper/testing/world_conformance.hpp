#pragma once
/// @file world_conformance.hpp
/// Conformance checks for world plugins (header-only, Catch2 v2; include <catch2/catch.hpp>
/// first). In the spirit of OMPL's StateSpace::sanityChecks(): the save/load round trip is a
/// fixpoint, malformed worlds are refused with `bad_world` naming the entry, copies are
/// independent, the free cells agree with the mask, `save_items`/`save_robot` are the parts of
/// `save`, and `load` keeps the host's cell limit exactly (docs/worlds.md). Every failure names its
/// scenario: the world asked for, what came back and what disagrees.
///
/// @code
///   FLIPPER_WORLD_CONFORMANCE("grid2d", [] { return load_plugin<sdk::World>("grid2d"); },
///                             kGoodWorldJson, {{R"({"robot": 3})", "robot"}})
/// @endcode

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::testing {

/// A malformed world and a piece of text its error message must contain (the offending entry).
struct BadWorld {
  std::string json;
  std::string names;
};

using WorldFactory = std::function<std::shared_ptr<sdk::World>()>;

/// Runs `load`, requires Error(bad_world) whose message contains `names`.
inline void require_bad_world(const sdk::World& world, const BadWorld& bad) {
  INFO("world: " << bad.json);
  try {
    (void)world.load(bad.json, ".");
    FAIL("accepted a malformed world");
  } catch (const sdk::Error& e) {
    INFO("message: " << e.what());
    REQUIRE(e.code() == sdk::codes::kBadWorld);
    REQUIRE(std::string(e.what()).find(bad.names) != std::string::npos);
  }
}

/// The mask, free_cells(), is_free() and the placement of robot and items agree; the
/// neighbourhood is symmetric (so path distances are).
inline void check_world_consistent(const sdk::WorldState& s) {
  INFO("the loaded state has " << (s.geometry ? "a" : "no") << " geometry and "
                               << (s.rooms ? "a" : "no") << " room map; want both");
  REQUIRE(s.geometry != nullptr);
  REQUIRE(s.rooms != nullptr);
  const sdk::Geometry& g = *s.geometry;
  const int dims = g.dims();
  INFO("the loaded world: bounds " << sdk::to_string(g.min(), dims) << " to "
                                   << sdk::to_string(g.max(), dims) << ", " << g.cell_count()
                                   << " cells, robot at " << sdk::to_string(s.robot, dims));
  INFO("size " << g.size_x() << " x " << g.size_y() << " x " << g.size_z()
               << "; want the cell count to be its product");
  REQUIRE(g.cell_count() == g.size_x() * g.size_y() * g.size_z());
  sdk::Area free;
  for (std::size_t i = 0; i < g.cell_count(); ++i) {
    const sdk::Cell c = g.cell_at(i);
    const bool agree = g.in_bounds(c) && g.index(c) == i && g.is_free(c) == (g.free_mask()[i] != 0);
    if (!agree) {  // (the message only when it fails: worlds have millions of cells)
      INFO("cell_at(" << i << ") = " << sdk::to_string(c, dims) << ": in_bounds " << g.in_bounds(c)
                      << ", index " << (g.in_bounds(c) ? g.index(c) : 0) << ", is_free "
                      << g.is_free(c) << ", mask " << int{g.free_mask()[i]}
                      << "; want in bounds, index " << i << " and is_free equal to the mask");
      REQUIRE(agree);
    }
    if (g.is_free(c)) free.push_back(c);
  }
  sdk::areas::normalize(free);
  INFO("free_cells() has " << g.free_cells().size() << " cells, the mask " << free.size()
                           << "; want the same cells");
  REQUIRE(free == g.free_cells());
  INFO("the robot's cell is " << (g.is_free(s.robot) ? "free" : "not free") << "; want free");
  REQUIRE(g.is_free(s.robot));
  for (const auto& li : s.items) {
    INFO("item " << li.item.id << " (" << li.item.color << " " << li.item.shape << ") lies at "
                 << sdk::to_string(li.at, dims) << ", which must be free");
    REQUIRE(g.is_free(li.at));
  }
  for (const sdk::Cell& o : g.neighbour_offsets()) {
    const sdk::Cell back{-o.x, -o.y, -o.z};
    INFO("the neighbour offset " << sdk::to_string(o, 3) << " has no opposite "
                                 << sdk::to_string(back, 3) << " (distances must be symmetric)");
    REQUIRE(std::find(g.neighbour_offsets().begin(), g.neighbour_offsets().end(), back) !=
            g.neighbour_offsets().end());
  }
  std::vector<std::int64_t> ids;
  for (const auto& li : s.items) ids.push_back(li.item.id);
  for (const auto& h : s.held) ids.push_back(h.id);
  std::sort(ids.begin(), ids.end());
  INFO("item ids (lying and held) must be distinct and below next_item_id " << s.next_item_id);
  REQUIRE(std::adjacent_find(ids.begin(), ids.end()) == ids.end());
  for (std::int64_t id : ids) REQUIRE(id < s.next_item_id);
}

/// Loads `good`, saves, loads the saved text and saves again: the texts agree and the states
/// are equal (robot, items, held items, rooms, bounds and mask).
inline void check_world_round_trip(const sdk::World& world, const std::string& good) {
  INFO(
      "round trip: load the good world, save it, load the saved text, save again; the good "
      "world: "
      << good);
  const sdk::WorldState a = world.load(good, ".");
  check_world_consistent(a);
  INFO("the loaded geometry has " << a.geometry->dims() << " dimensions, the plugin's dims() "
                                  << world.dims());
  REQUIRE(a.geometry->dims() == world.dims());
  const std::string saved = world.save(a);
  INFO("saved: " << saved);
  const sdk::WorldState b = world.load(saved, ".");
  check_world_consistent(b);
  INFO("saved again: " << world.save(b));
  REQUIRE(world.save(b) == saved);
  REQUIRE(b.robot == a.robot);
  REQUIRE(b.items == a.items);
  REQUIRE(b.held == a.held);
  REQUIRE(*b.rooms == *a.rooms);
  REQUIRE(b.next_item_id == a.next_item_id);
  REQUIRE(b.geometry->min() == a.geometry->min());
  REQUIRE(b.geometry->max() == a.geometry->max());
  REQUIRE(b.geometry->free_mask() == a.geometry->free_mask());
  REQUIRE(b.geometry->neighbour_offsets() == a.geometry->neighbour_offsets());
}

/// Copies share the immutable parts and never see each other's changes.
inline void check_world_copies(const sdk::World& world, const std::string& good) {
  INFO(
      "copies: a copy of the loaded good world moves its robot, drops its items and holds a new "
      "one; the original must not change. The good world: "
      << good);
  const sdk::WorldState a = world.load(good, ".");
  sdk::WorldState b = a;
  REQUIRE(b.geometry == a.geometry);  // shared, not copied
  REQUIRE(b.same_state(a));
  const sdk::Cell robot = a.robot;
  const auto items = a.items;
  const auto held = a.held;
  b.robot.x += 1;
  b.items.clear();
  b.held.push_back({b.next_item_id++, "red", "circle"});
  REQUIRE(a.robot == robot);
  REQUIRE(a.items == items);
  REQUIRE(a.held == held);
  REQUIRE(!b.same_state(a));
  // A second load of the same text gives the same contents.
  const sdk::WorldState c = world.load(good, ".");
  REQUIRE(c.robot == a.robot);
  REQUIRE(c.items == a.items);
}

/// The value of the top-level member `"key":` in a compact world text (as `save` writes it).
inline std::string saved_member(const std::string& text, const std::string& key, char open,
                                char close) {
  const std::string tag = "\"" + key + "\":";
  const auto at = text.find(tag);
  if (at == std::string::npos || at + tag.size() >= text.size() || text[at + tag.size()] != open)
    return {};
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = at + tag.size(); i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == open) {
      ++depth;
    } else if (c == close && --depth == 0) {
      return text.substr(at + tag.size(), i + 1 - at - tag.size());
    }
  }
  return {};
}

/// `save_items` and `save_robot` append exactly the "items" and "robot" values `save` writes,
/// for the loaded world and for a changed copy (the host writes later states from them).
inline void check_world_parts(const sdk::World& world, const std::string& good) {
  INFO("parts: save_items/save_robot must append the \"items\"/\"robot\" values of save()");
  sdk::WorldState s = world.load(good, ".");
  for (int round = 0; round < 2; ++round) {
    const std::string whole = world.save(s);
    INFO("save: " << whole);
    std::string items = "prefix", robot = "prefix";
    world.save_items(items, s);
    world.save_robot(robot, s);
    REQUIRE(items.rfind("prefix", 0) == 0);  // appended, not replaced
    REQUIRE(robot.rfind("prefix", 0) == 0);
    CHECK(items.substr(6) == saved_member(whole, "items", '[', ']'));
    CHECK(robot.substr(6) == saved_member(whole, "robot", '{', '}'));
    // A changed state: the first item picked up, or the robot's item dropped where it stands.
    if (!s.items.empty()) {
      s.held.push_back(s.items.front().item);
      s.items.erase(s.items.begin());
    } else if (!s.held.empty()) {
      s.items.push_back({s.held.back(), s.robot});
      s.held.pop_back();
    }
  }
}

/// `load` refuses a world of more cells than `limits.max_cells` with world_too_large and loads
/// it at exactly its cell count (the boundary N / N - 1).
inline void check_world_limits(const sdk::World& world, const std::string& good) {
  const std::uint64_t cells = world.load(good, ".").geometry->cell_count();
  INFO("limits: the good world has " << cells << " cells; it must load with max_cells = " << cells
                                     << " and be refused with " << cells - 1);
  sdk::WorldLimits limits;
  limits.max_cells = cells;
  REQUIRE(world.load(good, ".", limits).geometry->cell_count() == cells);
  limits.max_cells = cells - 1;
  try {
    (void)world.load(good, ".", limits);
    FAIL("loaded a world larger than max_cells");
  } catch (const sdk::Error& e) {
    INFO("message: " << e.what());
    REQUIRE(e.code() == sdk::codes::kWorldTooLarge);
  }
}

/// Malformed worlds every world plugin must refuse, whatever its space.
inline std::vector<BadWorld> generic_bad_worlds() {
  return {
      {"{", "JSON"},
      {"[]", "object"},
      {R"({"walls": [], "items": []})", "robot"},
      {R"({"robot": "here"})", "robot"},
      {R"({"robot": {"x": 0, "y": 0, "z": 0}, "items": 5})", "items"},
      {R"({"robot": {"x": 0, "y": 0, "z": 0}, "items": [{"x": 0, "y": 0, "z": 0, "color": 1, "shape": "circle"}]})",
       "items[0]: color"},
      {R"({"robot": {"x": 0.5, "y": 0, "z": 0}})", "robot: x"},
      {R"({"robot": {"x": 0, "y": 0, "z": 0}, "rooms": {"a": [], "a": []}})",
       "duplicate room name \"a\""},
      {R"({"robot": {"x": 0, "y": 0, "z": 0}, "rooms": []})", "rooms"},
      {R"({"robot": {"x": 0, "y": 0, "z": 0, "holding": [{"color": "red"}]}})", "robot.holding[0]"},
  };
}

/// All checks: round trip of `good`, copies, generic and plugin-specific bad worlds.
inline void check_world_conformance(const WorldFactory& factory, const std::string& good,
                                    const std::vector<BadWorld>& bad) {
  auto world = factory();
  REQUIRE(world != nullptr);
  check_world_round_trip(*world, good);
  check_world_copies(*world, good);
  check_world_parts(*world, good);
  check_world_limits(*world, good);
  for (const auto& b : generic_bad_worlds()) require_bad_world(*world, b);
  for (const auto& b : bad) require_bad_world(*world, b);
}

}  // namespace flipper::testing

/// Defines a Catch2 test case running every world check on the plugin from `factory`.
#define FLIPPER_WORLD_CONFORMANCE(name, factory, good_json, ...)                     \
  TEST_CASE(name ": world conformance", "[conformance][world]") {                    \
    ::flipper::testing::check_world_conformance(                                     \
        factory, good_json, std::vector<::flipper::testing::BadWorld>(__VA_ARGS__)); \
  }
