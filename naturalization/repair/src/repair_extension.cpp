// Repairs in a session (repair_extension.hpp, docs/protocol.md § "Repairs"): the query op's
// "repair" field, the session's parses for the chart and the edited sentences, the answer member.
#include "flipper/naturalization/repair_extension.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <utility>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::naturalization {
namespace {

// {"understood","words","nearest","teach"[,"limited"]}.
void write_repair(toolkit::json::JsonWriter& a, const Repair& r) {
  a.begin_object().key("understood").begin_array();
  for (const auto& p : r.understood) {
    a.begin_object().key("start").integer(p.start).key("end").integer(p.end);
    a.key("text").string(p.text).key("formula").string(sdk::render(p.program)).end_object();
  }
  a.end_array().key("words").begin_array();
  for (const auto& w : r.words) {
    a.begin_object().key("at").integer(w.at).key("word").string(w.word);
    a.key("kind").string(w.known ? "misplaced" : "unknown");
    if (!w.did_you_mean.empty()) a.key("did_you_mean").string(w.did_you_mean);
    a.end_object();
  }
  a.end_array().key("nearest").begin_array();
  for (const auto& s : r.nearest) {
    a.begin_object().key("text").string(s.text).key("formula").string(sdk::render(s.program));
    a.key("score").number(s.score).key("edits").integer(s.edits).key("edit").string(s.edit);
    a.end_object();
  }
  a.end_array();
  if (!r.teach_body.empty()) {
    a.key("teach").begin_object().key("op").string("define").key("head").string(r.teach_head);
    a.key("body").begin_array();
    for (const auto& line : r.teach_body) a.string(line);
    a.end_array().end_object();
  }
  if (!r.limited.empty()) a.key("limited").string(r.limited);
  a.end_object();
}

// {"unrealizable":[{"rank","step","at","why","variant","tried"[,"limited"]}]}.
void write_unrealizable(toolkit::json::JsonWriter& a, const std::vector<ExplainedCandidate>& cs,
                        int dims) {
  a.begin_object().key("unrealizable").begin_array();
  for (const auto& [rank, u] : cs) {
    a.begin_object().key("rank").unsigned_integer(rank);
    a.key("step").string(sdk::render(u.step)).key("at").begin_array();
    a.integer(u.at.x).integer(u.at.y);
    if (dims == 3) a.integer(u.at.z);
    a.end_array().key("why").string(u.why).key("variant");
    if (u.variant) {
      a.begin_object().key("formula").string(sdk::render(u.variant->program));
      a.key("edit").string(u.variant->edit).key("edits").integer(u.variant->edits).end_object();
    } else {
      a.null();
    }
    a.key("tried").unsigned_integer(u.tried);
    if (!u.limited.empty()) a.key("limited").string(u.limited);
    a.end_object();
  }
  a.end_array().end_object();
}

// The query's "repair" field: true asks for one; false, null and absent do not.
bool wants_repair(const kernel::Json& req) {
  const auto it = req.find("repair");
  if (it == req.end() || it->is_null()) return false;
  if (!it->is_boolean())
    throw sdk::Error(sdk::codes::kBadRequest,
                     "field 'repair' must be true or false (whether to explain a failure)");
  return it->get<bool>();
}

}  // namespace

std::vector<std::string> vocabulary(const kernel::Session& session) {
  std::vector<std::string> words;
  if (const auto& g = session.runtime().core_grammar) {
    for (const auto& r : g->rules)
      for (const auto& s : r->rhs)
        if (s.type == sdk::Symbol::Type::token) words.push_back(s.text);
    for (const auto* list : {&g->colors, &g->shapes, &g->directions})
      words.insert(words.end(), list->begin(), list->end());
  }
  session.emit(VocabularyAsked{session.user(), words});
  std::sort(words.begin(), words.end());
  words.erase(std::unique(words.begin(), words.end()), words.end());
  return words;
}

kernel::Json repair_json(const Repair& repair) {
  std::string text;
  toolkit::json::JsonWriter writer(text);
  write_repair(writer, repair);
  return kernel::Json::parse(text);
}

kernel::Json unrealizable_json(const std::vector<ExplainedCandidate>& explained, int dims) {
  std::string text;
  toolkit::json::JsonWriter writer(text);
  write_unrealizable(writer, explained, dims);
  return kernel::Json::parse(text);
}

std::shared_ptr<const Repair> repair_query(kernel::Session& session,
                                           const kernel::QueryResult& result) {
  const kernel::LastQuery& q = *result.query;
  if (!q.parse.candidates.empty()) return nullptr;
  RepairInput in;
  in.text = q.text;
  in.tokens = q.tokens;
  if (const auto& g = session.runtime().core_grammar) in.root = g->root;
  in.vocabulary = vocabulary(session);
  in.chart = session.parse(q.tokens, true, "repairing").chart;
  in.parse = [&session](const std::vector<std::string>& tokens) {
    return session.parse(tokens, false, "repairing").candidates;
  };
  return std::make_shared<const Repair>(find_repair(in));
}

std::vector<ExplainedCandidate> explain_unrealizable(const kernel::Session& session,
                                                     const kernel::QueryResult& result,
                                                     std::size_t first) {
  const kernel::LastQuery& q = *result.query;
  const RunProgram run = [&session](const sdk::Program& p, const sdk::WorldState& w) {
    return session.executor().run(p, w, session.request_stop());
  };
  std::vector<ExplainedCandidate> out;
  for (std::size_t i = 0; i < q.shown.size() && i < first; ++i) {
    const kernel::ShownCandidate& sc = q.shown[i];
    if (!decided_by_world(sc.outcome)) continue;
    out.push_back({sc.index, explain_unrealizable(q.parse.candidates[sc.index].program, q.world,
                                                  sc.outcome, run)});
  }
  return out;
}

void RepairExtension::attach(kernel::Session& session) {
  // The field is checked before the query runs: a bad one changes nothing.
  if (const kernel::Session::OpHandler* query = session.find_op("query"))
    session.set_op("query", [inner = *query](kernel::Session& s, const kernel::Json& req,
                                             toolkit::json::JsonWriter& a) {
      wants_repair(req);
      inner(s, req, a);
    });
  session.on<kernel::QueryWriting>([](const kernel::QueryWriting& e) {
    if (!wants_repair(e.request)) return;
    if (auto repair = repair_query(e.session, e.result)) {
      write_repair(e.answer.key("repair"), *repair);
      return;
    }
    const auto explained = explain_unrealizable(e.session, e.result);
    if (explained.empty()) return;  // every candidate is realizable: the answer is unchanged
    const auto& geometry = e.result.query->world.geometry;
    write_unrealizable(e.answer.key("repair"), explained, geometry ? geometry->dims() : 2);
  });
}

}  // namespace flipper::naturalization
