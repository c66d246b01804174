#pragma once
// Tiny plugin classes for kernel tests: enough behaviour to observe what the kernel hands them
// (params, grammar, world text), nothing else. Used by tests/plugins/*.cpp and bad/*.cpp.
#include <stdexcept>
#include <string>

#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/scorer.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::testplugins {

/// A size x size (x size in 3-D) free grid; world text containing "bad" is rejected.
class TestWorld : public sdk::World {
 public:
  explicit TestWorld(const sdk::Params& p)
      : size_(static_cast<int>(p.get_int("size"))), dims_(static_cast<int>(p.get_int("dims"))) {}
  static sdk::ParamSchema schema() {
    sdk::ParamSchema s;
    s.add_int("size", 5, "cells per side", 1, 100);
    s.add_int("dims", 2, "2 or 3", 2, 3);
    return s;
  }

 protected:
  sdk::WorldState do_load(std::string_view text, const std::string&) const override {
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
  std::string do_save(const sdk::WorldState&) const override { return "{}"; }
  int do_dims() const override { return dims_; }

 private:
  int size_;
  int dims_;
};

/// Plans nothing; reports the traits and params it was given.
class TestPlanner : public sdk::Planner {
 public:
  explicit TestPlanner(const sdk::Params& p)
      : supports_3d_(p.get_bool("supports_3d")),
        mode_(p.get_string("mode")),
        data_(p.has("data") ? p.get_string("data") : "") {}
  static sdk::ParamSchema schema() {
    sdk::ParamSchema s;
    s.add_bool("supports_3d", false, "claim 3-D support");
    s.add_string("mode", "plain", "a mode", {"plain", "fancy"});
    s.add_double("weight", 1.0, "a weight", 0.0, 10.0);
    s.add_path("data", std::nullopt, "a data file (resolved against the config dir)");
    return s;
  }
  const std::string& mode() const { return mode_; }
  const std::string& data() const { return data_; }

 protected:
  sdk::PathResult do_plan(const sdk::Geometry&, const sdk::PathRequest&,
                          const sdk::StopCondition&) const override {
    sdk::PathResult r;
    r.message = mode_ + "|" + data_;  // lets tests observe the validated params
    return r;
  }
  sdk::TourResult do_tour(const sdk::Geometry&, sdk::Cell, const std::vector<sdk::Cell>&,
                          const sdk::StopCondition&) const override {
    return {};
  }
  sdk::PlannerTraits do_traits() const override {
    sdk::PlannerTraits t;
    t.supports_3d = supports_3d_;
    return t;
  }

 private:
  bool supports_3d_;
  std::string mode_;
  std::string data_;
};

/// Parses nothing; remembers how many rules it was given (visible through `derivations`).
class TestParser : public sdk::Parser {
 public:
  explicit TestParser(const sdk::Params&) {}
  static sdk::ParamSchema schema() { return {}; }

 protected:
  void do_set_grammar(std::shared_ptr<const sdk::Grammar> g) override { rules_ = g->rules.size(); }
  void do_add_rule(sdk::RulePtr) override { ++rules_; }
  void do_remove_rule(const std::string&) override {}
  sdk::ParseResult do_parse(const sdk::ParseRequest&) const override {
    sdk::ParseResult r;
    r.derivations = rules_;
    return r;
  }

 private:
  std::size_t rules_ = 0;
};

class TestScorer : public sdk::Scorer {
 public:
  explicit TestScorer(const sdk::Params&) {}
  static sdk::ParamSchema schema() { return {}; }

 protected:
  double do_score_node(const sdk::Derivation&, const sdk::ScoreContext&) const override {
    return 0;
  }
  void do_features(const sdk::Derivation&, const sdk::ScoreContext&,
                   sdk::FeatureVector&) const override {}
  void do_learn(const std::vector<sdk::Candidate>&, std::size_t,
                const sdk::ScoreContext&) override {}
  std::string do_save_state() const override { return ""; }
  void do_load_state(std::string_view) override {}
};

}  // namespace flipper::testplugins
