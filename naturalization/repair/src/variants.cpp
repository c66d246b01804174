// The nearest realizable variant of an unrealizable program (unrealizable.hpp,
// docs/naturalization.md § 7): single edits of the failing step, nearest first, each whole
// edited program executed on the query's world with the query's executor and limits.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "unrealizable_parts.hpp"

namespace flipper::naturalization::detail {
namespace {

using sdk::Kind;
using sdk::Node;
using sdk::Program;

// Ties between edits at the same distance: going to the item a pick names first (every word the
// user said is kept), then item words (the place the user named is kept), dropped conditions,
// rooms, directions.
enum class EditKind { visit_first = 0, item_word = 1, drop = 2, room = 3, direction = 4 };

struct Edit {
  NodePath path;  // inside the step
  Program with;
  std::string text;
  int distance = 0;
  EditKind kind = EditKind::item_word;
};

// The colours and shapes of the world's items, lying or held (sorted, unique).
void item_words(const sdk::WorldState& w, std::set<std::string>& colors,
                std::set<std::string>& shapes) {
  for (const auto& li : w.items) {
    colors.insert(li.item.color);
    shapes.insert(li.item.shape);
  }
  for (const auto& h : w.held) {
    colors.insert(h.color);
    shapes.insert(h.shape);
  }
}

// The gap between two areas' bounding boxes, summed over the axes (0 when they overlap).
long box_gap(const sdk::Area& a, const sdk::Area& b) {
  const auto box = [](const sdk::Area& x) {
    sdk::Cell lo{std::numeric_limits<std::int32_t>::max(), std::numeric_limits<std::int32_t>::max(),
                 std::numeric_limits<std::int32_t>::max()};
    sdk::Cell hi{std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::min(),
                 std::numeric_limits<std::int32_t>::min()};
    for (const auto& c : x) {
      lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
      hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
    }
    return std::pair{lo, hi};
  };
  if (a.empty() || b.empty()) return std::numeric_limits<long>::max();
  const auto [alo, ahi] = box(a);
  const auto [blo, bhi] = box(b);
  const auto axis = [](long lo1, long hi1, long lo2, long hi2) {
    return std::max({0L, lo2 - hi1, lo1 - hi2});
  };
  return axis(alo.x, ahi.x, blo.x, bhi.x) + axis(alo.y, ahi.y, blo.y, bhi.y) +
         axis(alo.z, ahi.z, blo.z, bhi.z);
}

// The other rooms, nearest to `name` first (bounding-box gap, then name); by name when the
// world has no such room.
std::vector<std::string> rooms_near(const sdk::RoomMap& rooms, const std::string& name) {
  std::vector<std::pair<long, std::string>> order;
  const auto self = rooms.find(name);
  for (const auto& [other, cells] : rooms)
    if (other != name)
      order.emplace_back(self == rooms.end() ? 0 : box_gap(self->second, cells), other);
  std::sort(order.begin(), order.end());
  std::vector<std::string> out;
  out.reserve(order.size());
  for (auto& o : order) out.push_back(std::move(o.second));
  return out;
}

std::string quoted(const Program& p) {
  std::string t = sdk::render(p);
  if (t.size() >= 2 && t.front() == '{' && t.back() == '}') t = t.substr(1, t.size() - 2);
  return "'" + t + "'";
}

class EditFinder {
 public:
  explicit EditFinder(const sdk::WorldState& world) : world_(world) {
    item_words(world, colors_, shapes_);
  }

  std::vector<Edit> edits_of(const Program& step) {
    if (step->kind == Kind::Pick) {
      // `pick I` -> `visit world containing I ; pick I`: one statement inserted.
      const Program& i = step->kids[0];
      const Program item = i->kind == Kind::Every ? i->kids[0] : i;
      const Program where = sdk::make(Kind::AreaContaining, {sdk::make(Kind::World), item});
      edits_.push_back({{},
                        sdk::make_seq({sdk::make(Kind::VisitArea, {where}), step}),
                        "visit " + quoted(where) + " first",
                        1,
                        EditKind::visit_first});
    }
    NodePath path;
    walk(step, path);
    std::stable_sort(edits_.begin(), edits_.end(), [](const Edit& a, const Edit& b) {
      return std::pair{a.distance, a.kind} < std::pair{b.distance, b.kind};
    });
    return std::move(edits_);
  }

 private:
  void replace_word(const Node& n, const NodePath& path, const std::set<std::string>& words,
                    EditKind kind) {
    for (const auto& w : words)
      if (w != n.text)
        edits_.push_back(
            {path, sdk::make_word(n.kind, w), "replace '" + n.text + "' by '" + w + "'", 1, kind});
  }
  void drop(const Program& n, const NodePath& path, const Program& kept, const Program& dropped) {
    edits_.push_back({path, kept, "drop " + quoted(dropped),
                      static_cast<int>(n->size - (kept ? kept->size : 0)), EditKind::drop});
  }

  void walk(const Program& p, NodePath& path) {
    const Node& n = *p;
    switch (n.kind) {
      case Kind::Color:
        replace_word(n, path, colors_, EditKind::item_word);
        break;
      case Kind::Shape:
        replace_word(n, path, shapes_, EditKind::item_word);
        break;
      case Kind::Room: {
        const auto near = rooms_near(*world_.rooms, n.text);
        for (const auto& r : near)
          edits_.push_back({path, sdk::make_word(Kind::Room, r),
                            "replace '" + n.text + "' by '" + r + "'", 1, EditKind::room});
        break;
      }
      case Kind::Direction:
        for (const auto& [word, offset] : world_.geometry->directions())
          if (word != n.text)
            edits_.push_back({path, sdk::make_word(Kind::Direction, word),
                              "replace '" + n.text + "' by '" + word + "'", 1,
                              EditKind::direction});
        break;
      case Kind::Item:
        if (!n.kids.empty()) {
          // `item F` -> `item`: the whole condition; `F and G` -> `F` or `G`: one side.
          const Program filter = n.kids[0];
          drop(p, path, sdk::make(Kind::Item), filter);
        }
        break;
      case Kind::FilterAnd:
        drop(p, path, n.kids[1], n.kids[0]);
        drop(p, path, n.kids[0], n.kids[1]);
        break;
      default:
        break;
    }
    for (std::size_t k = 0; k < n.kids.size(); ++k) {
      path.push_back(k);
      walk(n.kids[k], path);
      path.pop_back();
    }
  }

  const sdk::WorldState& world_;
  std::set<std::string> colors_, shapes_;
  std::vector<Edit> edits_;
};

}  // namespace

void find_variant(const Program& program, const NodePath& step, const sdk::WorldState& world,
                  const RunProgram& run, Unrealizable& out) {
  Program node = program;
  for (std::size_t k : step) node = node->kids[k];
  const std::vector<Edit> edits = EditFinder(world).edits_of(node);
  CountedRun counted(run, kMaxVariantRuns);
  for (const Edit& e : edits) {
    NodePath at = step;
    at.insert(at.end(), e.path.begin(), e.path.end());
    Program edited;
    try {
      edited = replace_at(program, at, e.with);
    } catch (const sdk::Error&) {
      continue;  // not a well-formed program (make refused it): no variant
    }
    if (counted.used() == kMaxVariantRuns) {
      out.limited = "only the first " + std::to_string(kMaxVariantRuns) + " of " +
                    std::to_string(edits.size()) + " variants were tried";
      break;
    }
    const sdk::Outcome o = counted(edited, world);
    if (realized(o)) {
      out.variant = Variant{edited, e.text, e.distance};
      break;
    }
  }
  out.tried = counted.used();
  out.runs += counted.used();
}

}  // namespace flipper::naturalization::detail
