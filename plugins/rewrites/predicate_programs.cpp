#include "predicate_programs.hpp"

#include <algorithm>

namespace flipper::plugins::rewrites {

using sdk::Kind;
using sdk::Program;

std::vector<ItemPredicate> predicates_for(const std::vector<sdk::ItemInfo>& items) {
  std::vector<ItemPredicate> out{ItemPredicate{}};
  auto add = [&out](ItemPredicate p) {
    if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(std::move(p));
  };
  for (const auto& item : items) {
    add({item.color, ""});
    add({"", item.shape});
    add({item.color, item.shape});
  }
  return out;
}

Program item_program(const ItemPredicate& p) {
  std::vector<Program> filters;
  if (!p.color.empty())
    filters.push_back(sdk::make(Kind::FilterIs, {sdk::make_word(Kind::Color, p.color)}));
  if (!p.shape.empty())
    filters.push_back(sdk::make(Kind::FilterIs, {sdk::make_word(Kind::Shape, p.shape)}));
  if (filters.empty()) return sdk::make(Kind::Item);
  Program filter = filters.size() == 1 ? filters[0] : sdk::make(Kind::FilterAnd, filters);
  return sdk::make(Kind::Item, {filter});
}

Program visit_cell(const sdk::Cell& cell, int dims) {
  std::vector<Program> coords{sdk::make_num(cell.x), sdk::make_num(cell.y)};
  if (dims == 3) coords.push_back(sdk::make_num(cell.z));
  return sdk::make(Kind::VisitPoint, {sdk::make(Kind::PointXY, std::move(coords))});
}

Program visit_world_containing(const ItemPredicate& p) {
  Program area = sdk::make(Kind::AreaContaining, {sdk::make(Kind::World), item_program(p)});
  return sdk::make(Kind::VisitArea, {area});
}

Program pick_or_drop(Kind kind, const ItemPredicate& p, bool every) {
  Program item = item_program(p);
  if (every) item = sdk::make(Kind::Every, {item});
  return sdk::make(kind, {item});
}

bool only_moves(const Program& program) {
  switch (program->kind) {
    case Kind::Move:
      return true;
    case Kind::Seq:
      return std::all_of(program->kids.begin(), program->kids.end(),
                         [](const Program& k) { return only_moves(k); });
    case Kind::Repeat:
      return only_moves(program->kids[1]);
    default:
      return false;
  }
}

bool only_movement(const Program& program) {
  switch (program->kind) {
    case Kind::Move:
    case Kind::VisitPoint:
    case Kind::VisitArea:
    case Kind::VisitCollection:
      return true;
    case Kind::Seq:
      return std::all_of(program->kids.begin(), program->kids.end(),
                         [](const Program& k) { return only_movement(k); });
    case Kind::Strict:
      return only_movement(program->kids[0]);
    case Kind::Repeat:
    case Kind::ForeachPoint:
    case Kind::ForeachArea:
    case Kind::If:
    case Kind::While:
      return only_movement(program->kids[1]);
    default:
      return false;
  }
}

bool only_item_actions(const Program& program, Kind kind) {
  if (program->kind == kind) return true;
  switch (program->kind) {
    case Kind::Seq:
      return std::all_of(program->kids.begin(), program->kids.end(),
                         [kind](const Program& k) { return only_item_actions(k, kind); });
    case Kind::Strict:
      return only_item_actions(program->kids[0], kind);
    case Kind::Repeat:
      return only_item_actions(program->kids[1], kind);
    default:
      return false;
  }
}

bool trace_only(const std::vector<sdk::TraceStep>& trace, sdk::TraceStep::Act act) {
  return !trace.empty() && std::all_of(trace.begin(), trace.end(),
                                       [act](const sdk::TraceStep& s) { return s.act == act; });
}

}  // namespace flipper::plugins::rewrites
