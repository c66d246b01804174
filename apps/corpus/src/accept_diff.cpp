// Classifying execution disagreements on :accept records (see accept_diff.hpp).
#include "flipper/corpus/accept_diff.hpp"

#include <algorithm>
#include <iterator>
#include <nlohmann/json.hpp>

#include "tie_proofs.hpp"

namespace flipper::corpus {
namespace {

std::string item_text(const nlohmann::json& i) {
  return i.value("color", std::string()) + " " + i.value("shape", std::string());
}

struct Info {
  AcceptClass c;
  const char* id;
  const char* label;
};

// In AcceptClass order.
constexpr Info kInfo[] = {
    {AcceptClass::agree, "agree", "agree"},
    {AcceptClass::start_differs, "start_differs",
     "UNEXPLAINED: executed on another world than the logged world before"},
    {AcceptClass::budget_exceeded, "budget_exceeded", "ours: budget exceeded (§9 [decision])"},
    {AcceptClass::execution_error, "execution_error", "ours: execution error (§4.2/§9 [decision])"},
    {AcceptClass::reset, "reset", "reset: the next world is not reachable by a command"},
    {AcceptClass::no_change_logged, "no_change_logged",
     "no change logged: the next world equals the world before (client did not apply it)"},
    {AcceptClass::client_state, "client_state",
     "same trace as the original's own run; the logged next world differs (client state)"},
    {AcceptClass::failed_movement, "failed_movement",
     "failed movement leaves the robot in place (§6)"},
    {AcceptClass::loop_order, "loop_order", "loop order: tour T (§8 [decision])"},
    {AcceptClass::visit_collection, "visit_collection",
     "visit of a collection: shortest (§4.4 [decision])"},
    {AcceptClass::item_choice, "item_choice", "tie rules: item choice (§8 [decision])"},
    {AcceptClass::nearest_cell, "nearest_cell",
     "tie rules: nearest cell of an area (§8 [decision])"},
    {AcceptClass::unexplained, "unexplained", "UNEXPLAINED: worlds differ"},
    {AcceptClass::unreadable, "unreadable", "UNEXPLAINED: unreadable interpretation"},
};

const Info& info(AcceptClass c) {
  return kInfo[static_cast<std::size_t>(c)];
}

}  // namespace

WorldSnapshot snapshot(const nlohmann::json& w) {
  WorldSnapshot s;
  if (auto r = w.find("robot"); r != w.end()) {
    s.x = r->value("x", 0);
    s.y = r->value("y", 0);
    if (auto h = r->find("holding"); h != r->end())
      for (const auto& i : *h) s.held.push_back(item_text(i));
  }
  if (auto items = w.find("items"); items != w.end())
    for (const auto& i : *items)
      s.floor.push_back(std::to_string(i.value("x", 0)) + "," + std::to_string(i.value("y", 0)) +
                        " " + item_text(i));
  std::sort(s.held.begin(), s.held.end());
  std::sort(s.floor.begin(), s.floor.end());
  return s;
}

WorldSnapshot snapshot(const sdk::WorldState& w) {
  WorldSnapshot s;
  s.x = w.robot.x;
  s.y = w.robot.y;
  for (const auto& h : w.held) s.held.push_back(h.color + " " + h.shape);
  for (const auto& li : w.items)
    s.floor.push_back(std::to_string(li.at.x) + "," + std::to_string(li.at.y) + " " +
                      li.item.color + " " + li.item.shape);
  std::sort(s.held.begin(), s.held.end());
  std::sort(s.floor.begin(), s.floor.end());
  return s;
}

Steps our_steps(const std::vector<sdk::TraceStep>& trace) {
  Steps out;
  out.reserve(trace.size());
  for (const auto& s : trace) {
    std::string t = s.act == sdk::TraceStep::Act::move   ? "m"
                    : s.act == sdk::TraceStep::Act::pick ? "p"
                                                         : "d";
    t += " " + std::to_string(s.cell.x) + " " + std::to_string(s.cell.y);
    if (s.act != sdk::TraceStep::Act::move) t += " " + s.item.color + " " + s.item.shape;
    out.push_back(std::move(t));
  }
  return out;
}

Steps original_steps(const nlohmann::json& path, sdk::Cell robot) {
  Steps out;
  int x = robot.x, y = robot.y;
  for (const auto& e : path) {
    const int ex = e[0], ey = e[1];
    const std::string act = e[2];
    if (!e[5].get<bool>()) continue;  // possible = false
    if (act == "path" || act == "destination") {
      if (ex == x && ey == y) continue;
      x = ex;
      y = ey;
      out.push_back("m " + std::to_string(ex) + " " + std::to_string(ey));
    } else {
      const std::string colour = e[3], shape = e[4];
      out.push_back(std::string(act == "pickitem" ? "p" : "d") + " " + std::to_string(ex) + " " +
                    std::to_string(ey) + " " + colour + " " + shape);
    }
  }
  return out;
}

const char* class_id(AcceptClass c) {
  return info(c).id;
}
const char* class_label(AcceptClass c) {
  return info(c).label;
}
bool is_unexplained(AcceptClass c) {
  return c == AcceptClass::unexplained || c == AcceptClass::unreadable ||
         c == AcceptClass::start_differs;
}
const std::vector<AcceptClass>& all_classes() {
  static const std::vector<AcceptClass> all = [] {
    std::vector<AcceptClass> v;
    for (const auto& i : kInfo) v.push_back(i.c);
    return v;
  }();
  return all;
}

std::optional<AcceptClass> class_from_id(std::string_view id) {
  for (const auto& i : kInfo)
    if (id == i.id) return i.c;
  return std::nullopt;
}

AcceptClass classify_accept(const AcceptCase& c) {
  const sdk::Outcome& o = c.outcome;
  if (o.error)
    return o.error_code == "budget_exceeded" ? AcceptClass::budget_exceeded
                                             : AcceptClass::execution_error;
  const WorldSnapshot want = snapshot(c.after), got = snapshot(o.world), was = snapshot(c.before);
  if (got == want) return AcceptClass::agree;
  if (snapshot(c.start) != was) return AcceptClass::start_differs;
  // A reset: the client sent a world the command cannot have produced (another layout, items
  // that appear from nowhere or vanish), e.g. the study's start world again.
  const bool layout_changed =
      c.before.value("walls", nlohmann::json()) != c.after.value("walls", nlohmann::json()) ||
      c.before.value("rooms", nlohmann::json()) != c.after.value("rooms", nlohmann::json());
  const bool items_changed =
      want.floor.size() + want.held.size() != was.floor.size() + was.held.size();
  if (layout_changed || items_changed || c.next_world_id == kStudyStartWorld)
    return AcceptClass::reset;
  if (want == was) return AcceptClass::no_change_logged;
  if (c.original_path && our_steps(o.trace) == original_steps(*c.original_path, c.start.robot))
    return AcceptClass::client_state;
  const bool failed_move = std::any_of(o.warnings.begin(), o.warnings.end(), [](const auto& w) {
    return w.find("{move ") != std::string::npos || w.find("{visit ") != std::string::npos;
  });
  if (failed_move) return AcceptClass::failed_movement;
  // The tie-rule classes are proofs: another item choice, nearest cell or loop order, executed,
  // yields the logged world. Nothing else explains a difference.
  if (c.planner != nullptr)
    if (auto proven = detail::prove_tie(c.program, c.start, *c.planner, want)) return *proven;
  return AcceptClass::unexplained;
}

}  // namespace flipper::corpus
