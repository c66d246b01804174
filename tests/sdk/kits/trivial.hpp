#pragma once
// Tiny plugin classes for kernel tests: enough behaviour to observe what the kernel hands them
// (params, grammar, world text), nothing else. Used by tests/sdk/kits/*.cpp and bad/*.cpp.
#include <stdexcept>
#include <string>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/scorer.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::testplugins {

/// Every test plugin takes `throw_in`: the name of one of its calls that then throws a
/// std::runtime_error (not an sdk::Error), to see how the kernel names a failing plugin.
inline void add_throw_in(sdk::ParamSchema& s) {
  s.add_string("throw_in", "", "a call that throws on purpose (empty: none)");
}
inline void maybe_throw(const std::string& throw_in, const char* call) {
  if (throw_in == call) throw std::runtime_error(std::string("thrown on purpose in ") + call);
}

/// A size x size (x size in 3-D) free grid; world text containing "bad" is rejected.
class TestWorld : public sdk::World {
 public:
  explicit TestWorld(const sdk::Params& p)
      : size_(static_cast<int>(p.get_int("size"))),
        dims_(static_cast<int>(p.get_int("dims"))),
        throw_in_(p.get_string("throw_in")) {}
  static sdk::ParamSchema schema() {
    sdk::ParamSchema s;
    s.add_int("size", 5, "cells per side", 1, 100);
    s.add_int("dims", 2, "2 or 3", 2, 3);
    add_throw_in(s);
    return s;
  }

 protected:
  sdk::WorldState do_load(std::string_view text, const std::string&,
                          const sdk::WorldLimits&) const override {
    maybe_throw(throw_in_, "load");
    if (text.find("bad") != std::string_view::npos)
      throw sdk::Error(sdk::codes::kBadWorld, "test world: entry 'bad' is not allowed");
    const int zmax = dims_ == 3 ? size_ - 1 : 0;
    const std::size_t cells = static_cast<std::size_t>(size_) * size_ * (zmax + 1);
    sdk::WorldState w;
    w.geometry = std::make_shared<const sdk::Geometry>(
        dims_, sdk::Cell{0, 0, 0}, sdk::Cell{size_ - 1, size_ - 1, zmax},
        std::vector<std::uint8_t>(cells, 1),
        std::vector<sdk::Cell>{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}},
        std::vector<std::pair<std::string, sdk::Cell>>{{"right", {1, 0, 0}}});
    w.rooms = std::make_shared<const sdk::RoomMap>();
    return w;
  }
  std::string do_save(const sdk::WorldState&) const override {
    maybe_throw(throw_in_, "save");
    return "{}";
  }
  int do_dims() const override {
    maybe_throw(throw_in_, "dims");
    return dims_;
  }

 private:
  int size_;
  int dims_;
  std::string throw_in_;
};

/// Plans nothing; reports the traits and params it was given.
class TestPlanner : public sdk::Planner {
 public:
  explicit TestPlanner(const sdk::Params& p)
      : supports_3d_(p.get_bool("supports_3d")),
        mode_(p.get_string("mode")),
        data_(p.has("data") ? p.get_string("data") : ""),
        throw_in_(p.get_string("throw_in")) {}
  static sdk::ParamSchema schema() {
    sdk::ParamSchema s;
    s.add_bool("supports_3d", false, "claim 3-D support");
    s.add_string("mode", "plain", "a mode", {"plain", "fancy"});
    s.add_double("weight", 1.0, "a weight", 0.0, 10.0);
    s.add_path("data", std::nullopt, "a data file (resolved against the config dir)");
    add_throw_in(s);
    return s;
  }
  const std::string& mode() const { return mode_; }
  const std::string& data() const { return data_; }

 protected:
  sdk::PathResult do_plan(const sdk::Geometry&, const sdk::PathRequest&,
                          const sdk::StopCondition&) const override {
    maybe_throw(throw_in_, "plan");
    sdk::PathResult r;
    r.message = mode_ + "|" + data_;  // lets tests observe the validated params
    return r;
  }
  sdk::TourResult do_tour(const sdk::Geometry&, sdk::Cell, const std::vector<sdk::Cell>&,
                          const sdk::StopCondition&) const override {
    return {};
  }
  sdk::PlannerTraits do_traits() const override {
    maybe_throw(throw_in_, "traits");
    sdk::PlannerTraits t;
    t.supports_3d = supports_3d_;
    return t;
  }

 private:
  bool supports_3d_;
  std::string mode_;
  std::string data_;
  std::string throw_in_;
};

/// Parses nothing; remembers how many rules it was given (visible through `derivations`).
class TestParser : public sdk::Parser {
 public:
  explicit TestParser(const sdk::Params& p) : throw_in_(p.get_string("throw_in")) {}
  static sdk::ParamSchema schema() {
    sdk::ParamSchema s;
    add_throw_in(s);
    return s;
  }

 protected:
  void do_set_grammar(std::shared_ptr<const sdk::Grammar> g) override {
    maybe_throw(throw_in_, "set_grammar");
    rules_ = g->rules.size();
  }
  void do_add_rule(sdk::RulePtr) override { ++rules_; }
  void do_remove_rule(const std::string&) override {}
  sdk::ParseResult do_parse(const sdk::ParseRequest&) const override {
    maybe_throw(throw_in_, "parse");
    sdk::ParseResult r;
    r.derivations = rules_;
    return r;
  }

 private:
  std::size_t rules_ = 0;
  std::string throw_in_;
};

class TestScorer : public sdk::Scorer {
 public:
  explicit TestScorer(const sdk::Params& p) : throw_in_(p.get_string("throw_in")) {}
  static sdk::ParamSchema schema() {
    sdk::ParamSchema s;
    add_throw_in(s);
    return s;
  }

 protected:
  double do_score_node(const sdk::Derivation&, const sdk::ScoreContext&) const override {
    return 0;
  }
  void do_features(const sdk::Derivation&, const sdk::ScoreContext&,
                   sdk::FeatureVector&) const override {}
  void do_learn(const std::vector<sdk::Candidate>&, std::size_t,
                const sdk::ScoreContext&) override {}
  std::string do_save_state() const override {
    maybe_throw(throw_in_, "save_state");
    return "";
  }
  void do_load_state(std::string_view) override {}

 private:
  std::string throw_in_;
};

}  // namespace flipper::testplugins
