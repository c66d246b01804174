// The `rewrites` rewriter plugin: the four rewritings of docs/naturalization.md §6, in generation
// order. It only proposes; the kernel's generalizer checks equivalence and selects.
#include <algorithm>
#include <array>
#include <string>
#include <unordered_set>
#include <vector>

#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/sdk/rewriter.hpp"
#include "loop_rolling.hpp"
#include "predicate_programs.hpp"

namespace flipper::plugins::rewrites {

namespace {

using sdk::Kind;
using sdk::Program;

namespace param = sdk::param;

constexpr param::Int<std::size_t> kMaxCandidates{"max_candidates", 64, 0, 10000,
                                                 "most candidates proposed per definition"};
constexpr param::Int<std::size_t> kMaxBlock{"max_block", 10, 1, 30,
                                            "longest block of statements loop rolling repeats"};
constexpr param::Subset<4> kRewritings{
    "rewritings",
    {"loop", "moves_to_visit", "visit_by_predicate", "pick_by_predicate"},
    "rewritings to apply (loop, moves_to_visit, visit_by_predicate, pick_by_predicate), always "
    "in that order"};

// Collects candidates in order, without duplicates (or the body itself), up to a limit.
class CandidateList {
 public:
  CandidateList(const Program& body, std::size_t limit) : limit_(limit) { seen_.insert(body); }
  void add(Program program, const char* rewriting) {
    if (out_.size() >= limit_ || !seen_.insert(program).second) return;
    out_.push_back({std::move(program), rewriting});
  }
  bool full() const { return out_.size() >= limit_; }
  std::vector<sdk::RewriteCandidate> take() { return std::move(out_); }

 private:
  std::size_t limit_;
  std::unordered_set<Program, sdk::ProgramHash, sdk::ProgramEqual> seen_;
  std::vector<sdk::RewriteCandidate> out_;
};

}  // namespace

class Rewrites : public sdk::Rewriter {
 public:
  explicit Rewrites(const sdk::Params& params)
      : max_candidates_(param::get(params, kMaxCandidates)),
        max_block_(param::get(params, kMaxBlock)),
        enabled_(param::get(params, kRewritings)) {}

  static sdk::ParamSchema schema() { return param::schema(kMaxCandidates, kMaxBlock, kRewritings); }

 protected:
  std::vector<sdk::RewriteCandidate> do_propose(const sdk::RewriteRequest& req) const override {
    if (!req.body || req.body->sort != sdk::Sort::Action)
      throw sdk::Error(sdk::codes::kBadRequest, "rewrites: the body must be a statement");
    CandidateList list(req.body, max_candidates_);
    if (enabled_[0]) list.add(roll_loops(req.body, max_block_), "loop");
    if (list.full() || req.exec == nullptr || !(enabled_[1] || enabled_[2] || enabled_[3]))
      return list.take();

    // Rewritings 2-4 depend on what the body does in the world of the definition.
    const sdk::Outcome run = req.exec->run(req.body, req.before);
    if (run.error) return list.take();
    const sdk::Cell final_cell = run.world.robot;

    if (enabled_[1] && only_moves(req.body)) {
      const int dims = run.world.geometry ? run.world.geometry->dims() : 2;
      list.add(visit_cell(final_cell, dims), "moves_to_visit");
    }
    // Rewritings 3 and 4 replace the whole body, so they apply only when every statement of the
    // program is of their kind (a visit that left no trace step is still a statement).
    if (enabled_[2] && only_movement(req.body) &&
        trace_only(run.trace, sdk::TraceStep::Act::move)) {
      std::vector<sdk::ItemInfo> here;
      for (const auto& lying : run.world.items)
        if (lying.at == final_cell) here.push_back(lying.item);
      if (!here.empty())
        for (const auto& p : predicates_for(here))
          list.add(visit_world_containing(p), "visit_by_predicate");
    }
    if (enabled_[3]) {
      for (auto [act, kind] : {std::pair{sdk::TraceStep::Act::pick, Kind::Pick},
                               std::pair{sdk::TraceStep::Act::drop, Kind::Drop}}) {
        if (!only_item_actions(req.body, kind) || !trace_only(run.trace, act)) continue;
        std::vector<sdk::ItemInfo> moved;
        moved.reserve(run.trace.size());
        for (const auto& step : run.trace) moved.push_back(step.item);
        const char* name = kind == Kind::Pick ? "pick_by_predicate" : "drop_by_predicate";
        for (const auto& p : predicates_for(moved)) {
          list.add(pick_or_drop(kind, p, false), name);
          list.add(pick_or_drop(kind, p, true), name);
        }
      }
    }
    return list.take();
  }

 private:
  std::size_t max_candidates_;
  std::size_t max_block_;
  std::array<bool, 4> enabled_;  // by kRewritings' names
};

}  // namespace flipper::plugins::rewrites

FLIPPER_PLUGIN(flipper::plugins::rewrites::Rewrites, rewriter, "rewrites", FLIPPER_PLUGIN_VERSION,
               "Loop rolling, moves to visit, visit/pick/drop by predicate (naturalization §6)")
