// Flipper's trace as the original's path (see sempre_value.hpp).
#include "sempre_value.hpp"

#include <nlohmann/json.hpp>
#include <vector>

#include "flipper/toolkit/json/json_writer.hpp"

namespace flipper::studio {
namespace {

using Kind = sdk::Kind;
using Step = sdk::TraceStep;

// A string as nlohmann's dump() writes it with its default (strict) error handler: invalid UTF-8
// throws its type_error, as dumping the value's tree did.
void append_strict(std::string& out, const std::string& s) {
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x80 || c == '"' || c == '\\') {
      out += nlohmann::json(s).dump();
      return;
    }
  }
  out += '"';
  out += s;
  out += '"';
}

bool is_movement(Kind k) {
  return k == Kind::Move || k == Kind::VisitPoint || k == Kind::VisitArea ||
         k == Kind::VisitCollection;
}
bool is_item_action(Kind k) {
  return k == Kind::Pick || k == Kind::Drop || k == Kind::ItemAction;
}
const char* item_action_name(const sdk::Program& statement) {
  if (statement->kind == Kind::Drop) return "dropitem";
  if (statement->kind == Kind::ItemAction && !statement->kids.empty() &&
      statement->kids[0]->text == "drop")
    return "dropitem";
  return "pickitem";
}

// Whether the statement moves only with `move` (never `visit`): each of its steps is a movement.
bool moves_only(const sdk::Program& p) {
  if (p->kind == Kind::VisitPoint || p->kind == Kind::VisitArea || p->kind == Kind::VisitCollection)
    return false;
  for (const auto& k : p->kids)
    if (!moves_only(k)) return false;
  return true;
}

class PathWriter {
 public:
  explicit PathWriter(sdk::Cell robot) : at_(robot) {}

  // One statement's part of the execution: its trace steps, whether it failed, where it began.
  void statement(const sdk::Program& s, const std::vector<Step>& steps, bool failed) {
    if (is_movement(s->kind) && steps.empty()) {
      if (!failed) entry(at_, "destination");  // visiting the robot's own cell
      moved_ |= !failed;
      return;
    }
    if (is_item_action(s->kind) && steps.empty()) {
      if (failed) failed_item_action(item_action_name(s));
      return;
    }
    const bool each_step_a_movement = is_movement(s->kind) ? false : moves_only(s);
    for (std::size_t i = 0; i < steps.size(); ++i) {
      const Step& st = steps[i];
      if (st.act != Step::Act::move) {
        item(st);
        continue;
      }
      if (!moved_) entry(at_, "path");  // the first movement starts at the robot's cell
      moved_ = true;
      const bool last_of_run = i + 1 == steps.size() || steps[i + 1].act != Step::Act::move;
      at_ = st.cell;
      entry(at_, each_step_a_movement || last_of_run ? "destination" : "path");
    }
  }

  /// The path's entries, written: `[e1,e2,...]` without the brackets.
  const std::string& entries() const { return path_; }

 private:
  // Each entry is written as nlohmann dumps the array [x, y, action, color, shape, possible]
  // (the value used to be that tree, dumped).
  void begin(sdk::Cell c, const char* action) {
    if (!path_.empty()) path_ += ',';
    path_ += '[';
    toolkit::json::JsonWriter::append_integer(path_, c.x);
    path_ += ',';
    toolkit::json::JsonWriter::append_integer(path_, c.y);
    path_ += ",\"";
    path_ += action;
    path_ += "\",";
  }
  void entry(sdk::Cell c, const char* action) {
    begin(c, action);
    path_ += R"("null","null",true])";
  }
  void item(const Step& st) {
    begin(st.cell, st.act == Step::Act::pick ? "pickitem" : "dropitem");
    append_strict(path_, st.item.color);
    path_ += ',';
    append_strict(path_, st.item.shape);
    path_ += ",true]";
  }
  void failed_item_action(const char* action) {
    begin(at_, action);
    path_ += R"("null","null",false])";
  }

  sdk::Cell at_;
  bool moved_ = false;
  std::string path_;
};

// The statements a program runs one after the other: a sequence's statements and the copies of
// a `repeat` with a literal count, recursively; everything else is one statement. Stops adding
// (returns false) beyond `limit` statements.
bool split(const sdk::Program& p, std::vector<sdk::Program>& out, std::size_t limit) {
  if (p->kind == Kind::Seq) {
    for (const auto& k : p->kids)
      if (!split(k, out, limit)) return false;
    return true;
  }
  if (p->kind == Kind::Repeat && p->kids[0]->kind == Kind::Num) {
    const double n = p->kids[0]->number;
    if (n != static_cast<double>(static_cast<long long>(n))) return false;  // fails as a whole
    for (long long i = 0; i < static_cast<long long>(n); ++i)
      if (!split(p->kids[1], out, limit)) return false;
    return true;
  }
  out.push_back(p);
  return out.size() <= limit;
}

// Most statements one program is split into for its value (beyond: one compound statement).
constexpr std::size_t kMaxStatements = 1000;

// {"path": [...], "status": "<the last warning or empty>"}, as nlohmann dumps that object.
std::string value_text(const sdk::Outcome& whole, const PathWriter& writer) {
  std::string out;
  out.reserve(writer.entries().size() + 32);
  out += R"({"path":[)";
  out += writer.entries();
  out += R"(],"status":)";
  append_strict(out, whole.warnings.empty() ? std::string() : whole.warnings.back());
  out += '}';
  return out;
}

}  // namespace

std::string sempre_value(const sdk::Program& program, const sdk::WorldState& start,
                         const sdk::Outcome& whole, const sdk::ExecutionService& exec) {
  if (whole.error) return "execution error: " + *whole.error;
  PathWriter writer(start.robot);
  std::vector<sdk::Program> statements;
  const bool split_ok = split(program, statements, kMaxStatements);
  if (split_ok && statements.size() == 1) {
    writer.statement(statements[0], whole.trace, !whole.warnings.empty());
    return value_text(whole, writer);
  }
  bool apart = split_ok && statements.size() > 1;
  if (apart) {
    // The statements one by one: where each movement ends and which pick or drop failed.
    std::vector<sdk::Outcome> parts;
    std::vector<Step> joined;
    sdk::WorldState world = start;
    for (const auto& s : statements) {
      parts.push_back(exec.run(s, world));
      if (parts.back().error) break;
      world = parts.back().world;
      joined.insert(joined.end(), parts.back().trace.begin(), parts.back().trace.end());
    }
    // The same execution as a whole (it always is, unless a budget cut one of them).
    apart = parts.size() == statements.size() && joined == whole.trace;
    for (std::size_t i = 0; apart && i < parts.size(); ++i)
      writer.statement(statements[i], parts[i].trace, !parts[i].warnings.empty());
  }
  if (!apart) writer.statement(program, whole.trace, !whole.warnings.empty());
  return value_text(whole, writer);
}

}  // namespace flipper::studio
