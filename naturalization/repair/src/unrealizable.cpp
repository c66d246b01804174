// The failing step of an unrealizable program and why it fails in this world
// (unrealizable.hpp, docs/naturalization.md § 7): parts executed by the kernel's executor on the
// states they start from, and probe conditions for the reason.
#include "flipper/naturalization/unrealizable.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "unrealizable_parts.hpp"

namespace flipper::naturalization {
namespace detail {

sdk::Outcome CountedRun::operator()(const sdk::Program& program, const sdk::WorldState& world) {
  if (used_ >= cap_) throw OutOfRuns{};
  ++used_;
  sdk::Outcome o = run_(program, world);
  if (o.error_code == sdk::codes::kDeadlineExceeded)
    throw sdk::StoppedError(o.stopped, o.error.value_or("deadline exceeded"));
  return o;
}

bool realized(const sdk::Outcome& o) {
  return o.realizable && !o.error;
}

sdk::Program replace_at(const sdk::Program& root, const NodePath& path, const sdk::Program& with) {
  const auto rebuild = [&](const auto& self, const sdk::Program& node,
                           std::size_t depth) -> sdk::Program {
    if (depth == path.size()) return with;
    std::vector<sdk::Program> kids = node->kids;
    kids.at(path[depth]) = self(self, kids[path[depth]], depth + 1);
    return sdk::make(node->kind, std::move(kids));
  };
  return rebuild(rebuild, root, 0);
}

}  // namespace detail

namespace {

using detail::CountedRun;
using detail::NodePath;
using detail::realized;
using sdk::Kind;
using sdk::Node;
using sdk::Program;

// The failing step: where the descent stopped, the state it started from, and its outcome.
struct Step {
  Program node;
  NodePath path;
  sdk::WorldState state;
  sdk::Outcome outcome;
};

// Descends from the whole program to the smallest part that fails on the state it starts
// from: the first failing statement of a sequence, the body of a failing `strict` or `if`, the
// first failing round of a `repeat`. Loops over areas and points, `while` and primitives are
// steps (their bodies need the loop's variable or its rounds).
void descend(Step& st, CountedRun& run) {
  for (;;) {
    const Node& n = *st.node;
    sdk::WorldState at = st.state;
    std::optional<std::size_t> failing;
    std::optional<sdk::Outcome> failed;
    const auto try_kid = [&](std::size_t k) {
      sdk::Outcome o = run(n.kids[k], at);
      if (realized(o)) {
        at = std::move(o.world);
        return false;
      }
      failing = k;
      failed = std::move(o);
      return true;
    };
    if (n.kind == Kind::Seq) {
      for (std::size_t k = 0; k < n.kids.size(); ++k)
        if (try_kid(k)) break;
    } else if (n.kind == Kind::Strict) {
      try_kid(0);
    } else if (n.kind == Kind::If) {
      try_kid(1);  // the whole `if` failed, so its condition held and its body failed
    } else if (n.kind == Kind::Repeat && n.kids[0]->kind == Kind::Num) {
      const auto times = static_cast<std::int64_t>(n.kids[0]->number);
      for (std::int64_t i = 0; i < times; ++i)
        if (try_kid(1)) break;
    }
    if (!failing) return;
    st.node = n.kids[*failing];
    st.path.push_back(*failing);
    st.state = std::move(at);
    st.outcome = std::move(*failed);
  }
}

// The kernel's own reason for the step: its error, or the reason of its first warning
// (core-language §5: "Could not complete the action: TEXT (REASON)").
std::string kernel_reason(const Step& st) {
  if (st.outcome.error) return *st.outcome.error;
  if (st.outcome.warnings.empty()) return "it fails";
  const std::string& w = st.outcome.warnings.front();
  const std::string head = "Could not complete the action: " + sdk::render(st.node) + " (";
  if (w.size() > head.size() && w.compare(0, head.size(), head) == 0 && w.back() == ')')
    return w.substr(head.size(), w.size() - head.size() - 1);
  return w;
}

Program item_with(const Program& filter) {
  return filter ? sdk::make(Kind::Item, {filter}) : sdk::make(Kind::Item);
}
Program filter_of(const Program& item) {
  const Program& i = item->kind == Kind::Every ? item->kids[0] : item;
  return i->kids.empty() ? nullptr : i->kids[0];
}

// "red", "a circle": what `is W` says of an item.
std::string adjective(const Program& f) {
  if (f->kind == Kind::FilterIs) {
    const Node& w = *f->kids[0];
    if (w.kind == Kind::Color) return w.text;
    const bool vowel = !w.text.empty() && std::string("aeiou").find(w.text[0]) != std::string::npos;
    return std::string(vowel ? "an " : "a ") + w.text;
  }
  return sdk::render(f);
}

// "item", "red item", "circle", "red circle", "item {{is red} or {is blue}}".
std::string noun(const Program& f) {
  if (!f) return "item";
  if (f->kind == Kind::FilterIs)
    return f->kids[0]->kind == Kind::Color ? f->kids[0]->text + " item" : f->kids[0]->text;
  if (f->kind == Kind::FilterAnd && f->kids[0]->kind == Kind::FilterIs &&
      f->kids[1]->kind == Kind::FilterIs && f->kids[0]->kids[0]->kind == Kind::Color &&
      f->kids[1]->kids[0]->kind == Kind::Shape)
    return f->kids[0]->kids[0]->text + " " + f->kids[1]->kids[0]->text;
  return "item " + sdk::render(f);
}

class Reasons {
 public:
  Reasons(CountedRun& run, const Step& st) : run_(run), st_(st) {}

  std::string why() {
    const Node& n = *st_.node;
    switch (n.kind) {
      case Kind::Pick:
        return not_here(filter_of(n.kids[0]));
      case Kind::Drop:
        if (!holds(sdk::make(Kind::RobotHas, {item_with(nullptr)})))
          return "the robot holds nothing";
        return "the robot holds no " + noun(filter_of(n.kids[0]));
      case Kind::VisitArea:
        if (n.kids[0]->kind == Kind::AreaContaining)
          if (auto empty = empty_area(*n.kids[0])) return *empty;
        return from_here(kernel_reason(st_));
      case Kind::VisitCollection:
        if (n.kids[0]->kind == Kind::CollContaining) {
          const Program f = filter_of(n.kids[0]->kids[1]);
          if (!lies(f, sdk::make(Kind::World))) return nowhere(f);
        }
        return from_here(kernel_reason(st_));
      default:
        return from_here(kernel_reason(st_));
    }
  }

 private:
  // A probe: `if C {visit current}` runs one action exactly when C holds on the step's state.
  bool holds(const Program& condition) {
    const Program probe =
        sdk::make(Kind::If, {condition, sdk::make(Kind::VisitPoint, {sdk::make(Kind::Current)})});
    const sdk::Outcome o = run_(probe, st_.state);
    return !o.error && o.actions == 1;
  }
  bool lies(const Program& filter, const Program& area) {
    return holds(sdk::make(Kind::ItemAtArea, {item_with(filter), area}));
  }
  std::string cell() const {
    return sdk::to_string(st_.state.robot, st_.state.geometry ? st_.state.geometry->dims() : 2);
  }
  std::string from_here(std::string reason) const {
    if (reason.find("is unreachable") != std::string::npos)
      reason += " from the robot's position " + cell();
    return reason;
  }

  // No lying item matches `f` anywhere: which part of the description nothing has.
  std::string nowhere(const Program& f) {
    if (!f) return "no item lies in this world";
    if (f->kind == Kind::FilterAnd) {
      const bool a = lies(f->kids[0], sdk::make(Kind::World));
      const bool b = lies(f->kids[1], sdk::make(Kind::World));
      if (a && b)
        return "no item is both " + adjective(f->kids[0]) + " and " + adjective(f->kids[1]);
      return nowhere(a ? f->kids[1] : f->kids[0]);
    }
    return "no item is " + adjective(f);
  }

  // A pick found nothing on the robot's cell: where such items are, if anywhere.
  std::string not_here(const Program& f) {
    if (!lies(f, sdk::make(Kind::World))) return nowhere(f);
    std::string why = "no " + noun(f) + " at " + cell() + ", where the robot is";
    std::string in;
    for (const auto& [name, cells] : *st_.state.rooms)
      if (lies(f, sdk::make_word(Kind::Room, name))) in += (in.empty() ? "" : ", ") + name;
    return why + (in.empty() ? "; one lies outside every room" : "; one lies in " + in);
  }

  // `visit B containing I` found no cell: the reason when no such item lies in B.
  std::optional<std::string> empty_area(const Node& a) {
    const Program& place = a.kids[0];
    const Program f = filter_of(a.kids[1]);
    if (lies(f, place)) return std::nullopt;  // the area has cells: they are out of reach
    if (place->kind == Kind::World) return nowhere(f);
    std::string why =
        "no " + noun(f) + " in " + (place->kind == Kind::Room ? place->text : sdk::render(place));
    if (!lies(f, sdk::make(Kind::World))) why += " (" + nowhere(f) + ")";
    return why;
  }

  CountedRun& run_;
  const Step& st_;
};

}  // namespace

bool decided_by_world(const sdk::Outcome& outcome) {
  if (detail::realized(outcome)) return false;
  return !outcome.error || outcome.error_code == sdk::codes::kExecution;
}

Unrealizable explain_unrealizable(const sdk::Program& program, const sdk::WorldState& world,
                                  const sdk::Outcome& outcome, const RunProgram& run) {
  Unrealizable out;
  Step st{program, {}, world, outcome};
  CountedRun counted(run, kMaxExplainRuns);
  try {
    descend(st, counted);
    out.step = st.node;
    out.at = st.state.robot;
    out.why = Reasons(counted, st).why();
  } catch (const detail::OutOfRuns&) {
    out.step = st.node;
    out.at = st.state.robot;
    out.why = kernel_reason(st);
    out.limited =
        "the step and its reason took more than " + std::to_string(kMaxExplainRuns) + " executions";
  }
  out.runs = counted.used();
  if (out.limited.empty()) detail::find_variant(program, st.path, world, run, out);
  return out;
}

}  // namespace flipper::naturalization
