#include "flipper/naturalization/generalizer.hpp"

#include <cmath>
#include <exception>
#include <optional>
#include <set>
#include <unordered_set>
#include <utility>

#include "equivalence.hpp"
#include "flipper/sdk/errors.hpp"
#include "perturbation.hpp"

namespace flipper::naturalization {

namespace {

constexpr double kSimilarityTolerance = 1e-6;  // §6: similarities within 1e-6 count as equal
// Packing scores are sums of derivation scores; equal sums may differ in the last bits
// depending on the summation order, which must not decide a selection.
constexpr double kPackingTolerance = 1e-9;

// Lexicographic σ comparison; false on a tie so that the earlier entry stays.
bool beats(const GeneralizeCandidate& a, const GeneralizeCandidate& b) {
  if (std::abs(a.packing_score - b.packing_score) > kPackingTolerance)
    return a.packing_score > b.packing_score;
  if (std::abs(a.similarity - b.similarity) > kSimilarityTolerance)
    return a.similarity > b.similarity;
  if (a.perturbed_passed != b.perturbed_passed) return a.perturbed_passed > b.perturbed_passed;
  return a.generality > b.generality;
}

bool valid_statement(const sdk::Program& p) {
  return p && p->sort == sdk::Sort::Action && !sdk::has_holes(p) && sdk::loop_variables_bound(p);
}

void collect_property_words(const sdk::Program& p, std::set<std::string>& out) {
  if (p->kind == sdk::Kind::Color || p->kind == sdk::Kind::Shape || p->kind == sdk::Kind::Room)
    out.insert(p->text);
  for (const auto& k : p->kids) collect_property_words(k, out);
}

/// The colour, shape and room words of `candidate` that neither the head nor the body mentions:
/// a candidate using one narrows the meaning to what the definition's world happened to hold
/// (`drop the lot` := `drop every item` while holding only blue items must not become
/// `drop every item {is blue}`). World-equivalence cannot see this: in that world the
/// two agree.
std::string unmentioned_words(const sdk::Program& candidate, const std::set<std::string>& known) {
  std::set<std::string> words;
  collect_property_words(candidate, words);
  std::string out;
  for (const auto& w : words)
    if (!known.count(w)) out += (out.empty() ? "'" : ", '") + w + "'";
  return out;
}

// A body run on one perturbed world (perturbations where the body errs are left out: they say
// nothing about the body's meaning).
struct PerturbedRun {
  sdk::WorldState world;
  sdk::Outcome body;
};

// Every run of a generalization, the rewriter's included, goes through this: a run cut by a
// deadline must not pass for a program that errs (that would make the outcome depend on the
// machine's load), so the whole generalization is refused instead (docs/core-language.md §9).
class WatchedExecution final : public sdk::ExecutionService {
 public:
  explicit WatchedExecution(const sdk::ExecutionService& inner) : inner_(inner) {}
  sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world) const override {
    sdk::Outcome o = inner_.run(program, world);
    if (o.error_code == sdk::codes::kDeadlineExceeded && !stopped_) {
      stopped_ = o.error;
      cause_ = o.stopped;
    }
    return o;
  }
  void throw_if_stopped() const {
    if (stopped_)
      throw sdk::StoppedError(
          cause_, "deadline exceeded while generalizing the definition (" + *stopped_ + ")");
  }

 private:
  const sdk::ExecutionService& inner_;
  mutable std::optional<std::string> stopped_;
  mutable sdk::StopCause cause_ = sdk::StopCause::none;
};

}  // namespace

Generalizer::Generalizer(kernel::PluginRef<const sdk::Rewriter> rewriter,
                         kernel::PluginRef<const sdk::Similarity> similarity,
                         const sdk::ExecutionService& exec, GeneralizeOptions options)
    : rewriter_(std::move(rewriter)),
      similarity_(std::move(similarity)),
      exec_(exec),
      options_(options) {}

GeneralizeResult Generalizer::generalize(
    const std::vector<std::string>& head_tokens, const sdk::Program& body,
    const sdk::WorldState& before,
    const std::function<double(const sdk::Program&)>& packing_score) const {
  if (!valid_statement(body))
    throw sdk::Error(sdk::codes::kBadRequest, "generalize: the body must be a complete statement");

  const std::vector<std::string> head = head_words(head_tokens);
  std::set<std::string> mentioned(head_tokens.begin(), head_tokens.end());
  if (mentioned.count("grey")) mentioned.insert("gray");  // core-language §1
  collect_property_words(body, mentioned);
  auto score = [&](GeneralizeCandidate& c) {
    c.packing_score = packing_score ? packing_score(c.program) : 0.0;
    c.generality = -static_cast<int>(c.program->size);
    if (!similarity_) return;
    const double s = similarity_.call("similarity", [&](const sdk::Similarity& sim) {
      return sim.similarity(head, candidate_words(c.program));
    });
    c.similarity = std::isfinite(s) ? s : 0.0;
  };

  GeneralizeResult result;
  const WatchedExecution exec(exec_);
  const sdk::Outcome body_run = exec.run(body, before);

  std::vector<PerturbedRun> perturbed;
  if (!body_run.error)
    for (auto& w :
         generalize::perturb(before, options_.perturbed_checks, options_.perturbation_seed)) {
      sdk::Outcome o = exec.run(body, w);
      if (!o.error) perturbed.push_back({std::move(w), std::move(o)});
    }
  result.perturbations = static_cast<int>(perturbed.size());

  GeneralizeCandidate own;
  own.program = body;
  own.rewriting = "body";
  own.equivalent = !body_run.error;
  // The body is never discarded (it is the fallback winner); its own failure is reported as a
  // failed check, and every candidate is then rejected.
  if (body_run.error) own.failed_checks.push_back("execution error: " + *body_run.error);
  own.perturbed_passed = result.perturbations;
  score(own);
  result.candidates.push_back(std::move(own));

  std::vector<sdk::RewriteCandidate> proposals =
      rewriter_.call("propose", [&](const sdk::Rewriter& r) {
        return r.propose({body, before, &exec, head_tokens});
      });

  std::unordered_set<sdk::Program, sdk::ProgramHash, sdk::ProgramEqual> seen{body};
  for (auto& proposal : proposals) {
    // Repeated proposals carry no information; only the first occurrence is checked.
    if (proposal.program && !seen.insert(proposal.program).second) continue;
    GeneralizeCandidate c;
    c.program = std::move(proposal.program);
    c.rewriting = std::move(proposal.rewriting);
    if (!valid_statement(c.program)) {
      c.rejected_reason = "not a complete statement";
    } else if (auto why = generalize::difference(body_run, exec.run(c.program, before))) {
      c.rejected_reason = std::move(*why);
    } else if (auto words = unmentioned_words(c.program, mentioned); !words.empty()) {
      c.rejected_reason =
          "narrows the meaning with " + words + ", which neither the head nor the body mentions";
    } else {
      c.equivalent = true;
      for (std::size_t k = 0; k < perturbed.size(); ++k) {
        auto differs =
            generalize::difference(perturbed[k].body, exec.run(c.program, perturbed[k].world));
        if (differs)
          c.failed_checks.push_back("perturbation " + std::to_string(k + 1) + ": " + *differs);
        else
          ++c.perturbed_passed;
      }
      score(c);
    }
    result.candidates.push_back(std::move(c));
  }

  exec.throw_if_stopped();
  for (std::size_t i = 1; i < result.candidates.size(); ++i) {
    const auto& c = result.candidates[i];
    if (c.equivalent && beats(c, result.candidates[result.winner_index])) result.winner_index = i;
  }
  const auto& w = result.candidates[result.winner_index];
  result.winner = w.program;
  result.body_won = result.winner_index == 0;
  if (!result.body_won) result.winner_rewriting = w.rewriting;
  return result;
}

std::vector<sdk::WorldState> perturbed_worlds(const sdk::WorldState& world, int count,
                                              std::uint64_t seed) {
  return generalize::perturb(world, count, seed);
}

}  // namespace flipper::naturalization
