// The protocol ops of naturalization (docs/protocol.md: define, rules, delete_rule).
#include "flipper/naturalization/naturalize_ops.hpp"

#include "flipper/kernel/session_request.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::kernel {

Json rule_json(const sdk::Rule& rule) {
  Json rhs = Json::array();
  for (const auto& s : rule.rhs) rhs.push_back(s.text);
  return Json{{"id", rule.id},         {"lhs", rule.lhs},
              {"rhs", std::move(rhs)}, {"semantics", sdk::render(rule.sem)},
              {"author", rule.author}, {"how", sdk::to_string(rule.how)}};
}

namespace {

// The session's executor bound to the request's deadline (generalization runs many programs).
class DeadlineExecution : public sdk::ExecutionService {
 public:
  DeadlineExecution(const Executor& exec, std::chrono::steady_clock::time_point deadline)
      : exec_(exec), deadline_(deadline) {}
  sdk::Outcome run(const sdk::Program& program, const sdk::WorldState& world) const override {
    return exec_.run(program, world, deadline_);
  }

 private:
  const Executor& exec_;
  std::chrono::steady_clock::time_point deadline_;
};

// Head and body lines are parsed into a chart of (n + 1)^2 cells: bounded by input.max_tokens.
void check_length(const InputLimits& limits, const std::string& text, const std::string& what) {
  const std::size_t n = sdk::tokenize(text).size();
  if (n > limits.max_tokens)
    throw sdk::Error(sdk::codes::kInputTooLong, what + " has " + std::to_string(n) +
                                                    " tokens; the limit is input.max_tokens = " +
                                                    std::to_string(limits.max_tokens));
}

Json op_define(Naturalizer& nat, Session& s, const Json& req) {
  DefineRequest d;
  d.user = s.user();
  d.head = request::require_string(req, "head", "the utterance to define");
  d.body = request::require_string_list(req, "body", "a list of utterances");
  const InputLimits& limits = s.options().input;
  check_length(limits, d.head, "the head");
  if (d.body.size() > limits.max_body_lines)
    throw sdk::Error(sdk::codes::kInputTooLong, "the body has " + std::to_string(d.body.size()) +
                                                    " lines; the limit is input.max_body_lines = " +
                                                    std::to_string(limits.max_body_lines));
  for (std::size_t i = 0; i < d.body.size(); ++i)
    check_length(limits, d.body[i], "body line " + std::to_string(i + 1));
  if (req.contains("ranks") && !req["ranks"].is_null()) {
    if (!req["ranks"].is_array())
      throw sdk::Error(sdk::codes::kBadRequest, "field 'ranks' must be a list of integers");
    for (const auto& r : req["ranks"]) {
      // get<int> would wrap a large rank into a small (even valid) one.
      if (!r.is_number_integer() || r < 0 || r > 1000000)
        throw sdk::Error(
            sdk::codes::kBadRequest,
            "field 'ranks' must be a list of integers from 0 to 1000000, got " + r.dump());
      d.body_ranks.push_back(r.get<int>());
    }
  }
  const DeadlineExecution exec(s.executor(), s.deadline());
  d.before = &s.world();
  d.exec = &exec;
  d.deadline = s.deadline();
  DefineOutcome out = nat.define(d);
  Json rules = Json::array();
  for (const auto& r : out.rules) rules.push_back(rule_json(*r));
  Json answer{{"rules", std::move(rules)},
              {"generalized", out.generalized ? Json(sdk::render(out.generalized)) : Json()}};
  if (out.generalization_ran) {
    Json discarded = Json::array();
    for (const auto& c : out.discarded)
      discarded.push_back({{"formula", c.program ? sdk::render(c.program) : std::string()},
                           {"rewriting", c.rewriting},
                           {"reason", c.reason}});
    answer["discarded"] = std::move(discarded);
  }
  return answer;
}

Json op_rules(Naturalizer& nat, Session& s, const Json& req) {
  const auto author = request::optional_string(req, "author", "a user name");
  Json rules = Json::array();
  for (const auto& l : nat.rules(s.user(), author)) {
    Json j = rule_json(*l.rule);
    j["head"] = l.rule->head;
    j["body"] = l.rule->body;
    j["uses"] = l.uses_by_author + l.uses_by_others;
    j["uses_by_author"] = l.uses_by_author;
    j["uses_by_others"] = l.uses_by_others;
    rules.push_back(std::move(j));
  }
  return Json{{"rules", std::move(rules)}};
}

Json op_delete_rule(Naturalizer& nat, Session& s, const Json& req) {
  const std::string id = request::require_string(req, "rule", "a rule id");
  nat.delete_rule(s.user(), id);
  return Json{{"deleted", id}};
}

}  // namespace

void install_naturalization(Session& session, std::shared_ptr<Naturalizer> nat) {
  session.set_op("define", [nat](Session& s, const Json& r) { return op_define(*nat, s, r); });
  session.set_op("rules", [nat](Session& s, const Json& r) {
    nat->refresh();
    return op_rules(*nat, s, r);
  });
  // Every parse sees the rules and deletions other processes committed before it.
  if (const auto* query_op = session.find_op("query")) {
    Session::OpHandler inner = *query_op;
    session.set_op("query", [nat, inner](Session& s, const Json& r) {
      nat->refresh();
      return inner(s, r);
    });
  }
  session.set_op("delete_rule",
                 [nat](Session& s, const Json& r) { return op_delete_rule(*nat, s, r); });
  if (nat->options().sharing != Sharing::shared)
    session.set_visibility(
        [nat](const sdk::Rule& rule, const std::string& user) { return nat->visible(rule, user); });
  session.set_on_accept(
      [nat](Session&, const AcceptEvent& e) { nat->on_accept(e.user, e.candidate.induced_rules); });
  if (nat->options().per_user_weights) {
    if (const auto* user_op = session.find_op("user")) {
      Session::OpHandler inner = *user_op;
      session.set_op("user", [nat, inner](Session& s, const Json& r) {
        Json answer = inner(s, r);
        nat->select_user(s.user());
        return answer;
      });
    }
    nat->select_user(session.user());
  }
}

std::shared_ptr<Naturalizer> install_naturalization(Session& session,
                                                    std::shared_ptr<Runtime> runtime) {
  NaturalizeOptions options = NaturalizeOptions::from_config(runtime->config);
  auto nat = std::make_shared<Naturalizer>(std::move(runtime), std::move(options));
  install_naturalization(session, nat);
  return nat;
}

void NaturalizationExtension::install(Session& session) {
  install_naturalization(session, naturalizer_);
}

void NaturalizationExtension::activate(const Session& session) {
  if (naturalizer_->options().per_user_weights) naturalizer_->select_user(session.user());
}

}  // namespace flipper::kernel
