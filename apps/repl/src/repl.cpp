// The interactive loop: utterances become queries; a number accepts, `r` rejects, `m` shows more
// readings; `:` commands (help text below).
#include <algorithm>
#include <charconv>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <sstream>
#include <vector>

#include <fstream>

#include "flipper/naturalization/naturalize_ops.hpp"
#include "flipper/naturalization/repair_extension.hpp"
#include "flipper/repl/outcome_json.hpp"
#include "flipper/repl/repl.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/svg/svg.hpp"

namespace flipper::repl {
namespace {

// How many readings one query keeps for paging with `m` (each is planned, so not unbounded).
constexpr int kKeep = 30;

// The commands; guide_help_text() adds the constructs and sections of docs/language.md.
const char* kCommands =
    "Type an utterance (e.g. `visit room1; pick item is red`) to see its readings, each with its\n"
    "path drawn on the map (o path, E end, P pick, D drop).\n"
    "  N              choose reading N (the robot does it; the map keeps its trail)\n"
    "  m              show more readings        r     reject all shown readings\n"
    "  :define HEAD   teach HEAD (default: the last utterance); then one body line per\n"
    "                 line, each checked as you type it, ending with an empty line;\n"
    "                 Ctrl-C (or :cancel) abandons the definition\n"
    "  :preview HEAD  the same, but first shows the rules it would induce, new sentences each\n"
    "                 makes understandable and what they would do here; then store, drop\n"
    "                 some rules (e.g. `new2`), or cancel\n"
    "  :undo          put the world back as it was before the last choice or :world\n"
    "  :rules         list the rules you can use, with their ids\n"
    "  :delete ID     delete a rule you defined (ids from :rules)\n"
    "  :world FILE    load a world file         :user NAME   set the current user\n"
    "  :map           show the world            :floor Z     show floor Z of a 3-D world\n"
    "  :save FILE     the world (and the plan just chosen) as an SVG picture\n"
    "  :examples      one example of every construct, with its result on the study map\n"
    "  :help          this text                 :quit        leave (also Ctrl-D)\n"
    "  Ctrl-C         drop the line being typed (or the answer of a query still running)\n";

std::string trim(const std::string& s) {
  auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::string rhs_text(const sdk::Rule& r) {
  std::string rhs;
  for (const auto& symbol : r.rhs) rhs += (rhs.empty() ? "" : " ") + symbol.text;
  return rhs;
}

// "  r1  zig zag -> ...  =>  {...}"
std::string rule_text(const sdk::Rule& r) {
  return "  " + r.id + "  " + r.lhs + " -> " + rhs_text(r) + "  =>  " + sdk::render(r.sem);
}

// "  r1  zig zag -> ...  =>  {...}  (by ana, used 2x)"
std::string describe_rule(const naturalization::RuleListing& l) {
  return rule_text(*l.rule) + "  (by " + l.rule->author + ", used " +
         std::to_string(l.uses_by_author + l.uses_by_others) + "x)\n";
}

// A shown candidate in the protocol's candidate shape (docs/protocol.md § query), the input of
// the candidate view.
kernel::Json candidate_view(const kernel::LastQuery& q, const kernel::ShownCandidate& sc) {
  const sdk::Candidate& c = q.parse.candidates[sc.index];
  const int dims = q.world.geometry ? q.world.geometry->dims() : 2;
  kernel::Json rules = kernel::Json::array(), authors = kernel::Json::array();
  for (const auto& r : sc.induced_rules) {
    rules.push_back(r->id);
    if (std::find(authors.begin(), authors.end(), r->author) == authors.end())
      authors.push_back(r->author);
  }
  kernel::Json v{{"formula", sdk::render(c.program)},
                 {"prob", q.probs[sc.index]},
                 {"induced", !c.core_only},
                 {"rules", std::move(rules)},
                 {"authors", std::move(authors)},
                 {"realizable", sc.outcome.realizable && !sc.outcome.error},
                 {"trace", trace_json(sc.outcome.trace, dims)},
                 {"warnings", strings_json(sc.outcome.warnings)}};
  if (sc.error_code) v["error"] = error_json(*sc.error_code, sc.outcome.error.value_or(""));
  return v;
}

std::optional<int> parse_int(const std::string& s) {
  int n = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), n);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return n;
}

class Repl {
 public:
  Repl(kernel::Session& s, LineReader& r, std::ostream& o)
      : session_(s), reader_(r), out_(o), page_(std::max(1, s.options().k)) {}

  int run() {
    out_ << "Flipper -- precise but natural robot tasks. :help for commands.\n";
    show_map();
    std::string line;
    for (;;) {
      const auto read = reader_.read("flipper> ", line);
      if (read == LineReader::Read::end) break;
      if (read == LineReader::Read::interrupted) {
        // Ctrl-C drops the line; on an empty one the user may be trying to leave.
        if (trim(line).empty()) out_ << "(:quit or Ctrl-D leaves)\n";
        out_.flush();
        continue;
      }
      line = trim(line);
      if (line.empty()) continue;
      if (line[0] == ':') {
        if (!command(line)) break;
      } else if (!readings_.empty() && choice(line)) {
      } else if (!readings_.empty() && line == "m") {
        show_more();
      } else if (!readings_.empty() && line == "r") {
        out_ << "Rejected. Rephrase it, or teach it with :define.\n";
        readings_ = kernel::Json::array();
      } else {
        query(line);
      }
      out_.flush();
    }
    out_ << "bye\n";
    out_.flush();
    return 0;
  }

 private:
  // Runs a typed session call; a refusal is printed as the protocol names it. False then.
  template <class F>
  bool call(F&& f) {
    try {
      f();
      return true;
    } catch (const sdk::Error& e) {
      out_ << "error (" << e.code() << "): " << e.what() << '\n';
    } catch (const std::exception& e) {
      out_ << "error (" << sdk::codes::kInternal << "): internal error: " << e.what() << '\n';
    }
    return false;
  }

  // The lexicon's define/rules/delete service (null in a session without naturalization).
  naturalization::NaturalizationExtension* lexicon() {
    auto* nat = session_.extension<naturalization::NaturalizationExtension>();
    if (nat == nullptr) out_ << "error (unknown_op): this session has no lexicon\n";
    return nat;
  }

  kernel::Json world_view(const sdk::WorldState& state) {
    kernel::Json world;
    call([&] { world = session_.world_json(state); });
    return world;
  }

  MapOptions map_options(const kernel::Json* trace = nullptr, bool legend = true) const {
    MapOptions o;
    o.trace = trace;
    o.legend = legend;
    o.floor = floor_;
    return o;
  }

  void show_map() {
    const kernel::Json world = world_view(session_.world());
    if (!world.is_null()) out_ << render_map(world, map_options());
  }

  // "Unknown words: 'vist' (did you mean 'visit'?).\n" or empty.
  std::string unknown_words_note(const std::string& text) {
    const std::string note = repl::unknown_words_note(session_, text);
    return note.empty() ? note : note + "\n";
  }

  void query(const std::string& text) {
    last_text_ = text;
    trail_ = kernel::Json();
    readings_ = kernel::Json::array();
    shown_ = 0;
    query_world_ = world_view(session_.world());  // the paths start here
    kernel::QueryResult result;
    std::shared_ptr<const naturalization::Repair> repair;
    std::vector<naturalization::ExplainedCandidate> explained;
    const kernel::QueryRequest request{text, kKeep};
    const bool ok = call([&] {
      result = session_.query(request);
      // A failure says how to repair it (docs/protocol.md "Repairs"); so does a reading of the
      // first page that cannot be done here (docs/naturalization.md §7).
      repair = naturalization::repair_query(session_, result);
      explained =
          naturalization::explain_unrealizable(session_, result, static_cast<std::size_t>(page_));
    });
    // The session cannot be stopped mid-query (session.deadline_ms bounds it); Ctrl-C while it
    // ran drops its answer.
    if (reader_.take_interrupt()) {
      out_ << "\nCancelled (Ctrl-C): the readings are not shown.\n";  // after the echoed ^C
      return;
    }
    if (!ok) return;
    if (result.query->shown.empty()) {
      const std::string note = unknown_words_note(text);
      out_ << "I did not understand that. " << note
           << (note.empty() ? "" : "Fix the spelling, or teach the phrase with `:define`.\n")
           << (note.empty() ? "Teach me with `:define` (then the steps, one per line).\n" : "");
      if (repair) out_ << repair_lines(*repair);
      return;
    }
    const auto& shown = result.query->shown;
    const int dims = result.query->world.geometry ? result.query->world.geometry->dims() : 2;
    for (const kernel::ShownCandidate& sc : shown) {
      readings_.push_back(candidate_view(*result.query, sc));
      for (const auto& e : explained)
        if (e.rank == sc.index) readings_.back()["why"] = unrealizable_line(e.explanation, dims);
    }
    total_ = result.total();
    out_ << "Readings (" << result.status << "):\n";
    show_more();
  }

  // The next page of readings, each with its path on a compact map.
  void show_more() {
    const int kept = static_cast<int>(readings_.size());
    if (shown_ >= kept) {
      out_ << "No more readings (" << kept << " of " << total_ << " kept). Choose 1.." << kept
           << ".\n";
      return;
    }
    const int until = std::min(kept, shown_ + page_);
    for (int i = shown_; i < until; ++i) {
      const kernel::Json& c = readings_[static_cast<std::size_t>(i)];
      out_ << describe_candidate(c, i + 1);
      if (c.contains("why")) out_ << "      " << c["why"].get<std::string>() << "\n";
      const kernel::Json& trace = c["trace"];
      if (!trace.empty() && query_world_.is_object() && !c.contains("error"))
        out_ << indent(render_map(query_world_, map_options(&trace, false)));
    }
    shown_ = until;
    out_ << shown_ << " of " << total_ << " shown. Choose 1.." << shown_;
    if (shown_ < kept) out_ << ", m for more";
    out_ << ", or r to reject all.\n";
  }

  static std::string indent(const std::string& text) {
    std::string out;
    std::size_t start = 0;
    while (start < text.size()) {
      const std::size_t nl = text.find('\n', start);
      out += "      " + text.substr(start, nl - start + 1);
      if (nl == std::string::npos) break;
      start = nl + 1;
    }
    return out;
  }

  bool choice(const std::string& line) {
    const auto n = parse_int(line);
    if (!n) return false;
    if (*n < 1 || *n > shown_) {
      out_ << "Choose a number from 1 to " << shown_ << ".\n";
      return true;
    }
    const sdk::WorldState before = session_.world();
    kernel::AcceptResult accepted;
    if (!call([&] { accepted = session_.accept(kernel::AcceptRequest{*n - 1}); })) return true;
    const sdk::Outcome& o = accepted.outcome;
    undo_.push_back(before);
    trail_ = trace_json(o.trace, o.world.geometry ? o.world.geometry->dims() : 2);
    trail_title_ = readings_[static_cast<std::size_t>(*n - 1)].value("formula", std::string());
    trail_world_ = query_world_;
    readings_ = kernel::Json::array();
    std::size_t steps = 0;
    for (const auto& s : o.trace) steps += s.act == sdk::TraceStep::Act::move;
    out_ << "Done: " << steps << (steps == 1 ? " step" : " steps") << ". (:undo puts it back)\n";
    for (const auto& w : collapse_warnings(strings_json(o.warnings)))
      out_ << "warning: " << w << '\n';
    const kernel::Json world = world_view(o.world);
    if (!world.is_null()) out_ << render_map(world, map_options(&trail_));
    return true;
  }

  bool command(const std::string& line) {
    auto space = line.find(' ');
    std::string cmd = line.substr(0, space);
    std::string arg = space == std::string::npos ? "" : trim(line.substr(space + 1));
    if (cmd == ":quit" || cmd == ":q" || cmd == ":exit") return false;
    if (cmd == ":help" || cmd == ":h") {
      out_ << kCommands << guide_help_text();
    } else if (cmd == ":examples") {
      out_ << examples_text();
    } else if (cmd == ":map" || cmd == ":state") {
      show_map();
    } else if (cmd == ":floor") {
      const auto& geometry = session_.world().geometry;
      if (!geometry || geometry->dims() != 3) {
        out_ << "This world is flat (2-D): it has no floors, and the map shows all of it. "
                ":floor is for 3-D worlds.\n";
        return true;
      }
      const auto z = parse_int(arg);
      if (!z) {
        out_ << "usage: :floor Z (a z coordinate of a 3-D world)\n";
        return true;
      }
      if (*z < geometry->min().z || *z > geometry->max().z) {
        out_ << "There is no floor " << *z
             << ": this world's floors go from z = " << geometry->min().z << " to "
             << geometry->max().z << ".\n";
        return true;
      }
      floor_ = *z;
      show_map();
    } else if (cmd == ":world") {
      if (arg.empty()) {
        out_ << "usage: :world FILE\n";
        return true;
      }
      const sdk::WorldState before = session_.world();
      if (call([&] { session_.open_world_file(arg); })) {
        undo_.push_back(before);
        readings_ = kernel::Json::array();
        floor_.reset();
        show_map();
      }
    } else if (cmd == ":save") {
      save(arg);
    } else if (cmd == ":undo") {
      undo();
    } else if (cmd == ":user") {
      if (arg.empty()) {
        out_ << "usage: :user NAME\n";
        return true;
      }
      if (call([&] { session_.set_user(arg); })) out_ << "You are " << session_.user() << ".\n";
    } else if (cmd == ":rules") {
      std::vector<naturalization::RuleListing> rules;
      auto* nat = lexicon();
      if (nat != nullptr && call([&] { rules = nat->rules(session_, std::nullopt); })) {
        if (rules.empty()) out_ << "No rules.\n";
        for (const auto& r : rules) out_ << describe_rule(r);
        if (!rules.empty()) out_ << "(:delete ID removes one of your own rules)\n";
      }
    } else if (cmd == ":delete") {
      if (arg.empty()) {
        out_ << "usage: :delete ID (ids from :rules)\n";
        return true;
      }
      auto* nat = lexicon();
      if (nat != nullptr && call([&] { nat->delete_rule(session_, arg); }))
        out_ << "Deleted rule " << arg << ".\n";
    } else if (cmd == ":define") {
      define(arg.empty() ? last_text_ : arg);
    } else if (cmd == ":preview") {
      define(arg.empty() ? last_text_ : arg, true);
    } else {
      out_ << "Unknown command " << cmd << ". :help lists the commands.\n";
    }
    return true;
  }

  // The picture: the plan just chosen on the world it started from, else the current world.
  void save(const std::string& file) {
    if (file.empty()) {
      out_ << "usage: :save FILE (an SVG picture of the world and the plan just chosen)\n";
      return;
    }
    std::string picture;
    if (trail_.is_array()) {
      picture = svg::world_picture(trail_world_, &trail_, trail_title_);
    } else {
      picture = svg::world_picture(session_.world_json(session_.world()), nullptr, "world");
    }
    std::ofstream f(file);
    f << picture;
    f.flush();
    if (!f) {
      out_ << "error (io): cannot write '" << file << "'\n";
      return;
    }
    out_ << "Saved " << (trail_.is_array() ? "the plan and its world" : "the world") << " to "
         << file << ".\n";
  }

  void undo() {
    if (undo_.empty()) {
      out_ << "Nothing to undo.\n";
      return;
    }
    session_.set_world(undo_.back());
    undo_.pop_back();
    readings_ = kernel::Json::array();
    out_ << "Undone: the world is as it was before the last choice (what the ranking learned "
            "from it stays).\n";
    show_map();
  }

  // Reads one line of a definition; false when the user cancelled (Ctrl-C, :cancel) or input
  // ended.
  bool read_definition_line(const char* prompt, std::string& line) {
    if (reader_.read(prompt, line) != LineReader::Read::line || trim(line) == ":cancel") {
      out_ << "Definition cancelled; nothing was learned.\n";
      return false;
    }
    line = trim(line);
    return true;
  }

  // A preview (docs/naturalization.md §5 "Preview"): each rule with its example sentences and
  // what they would do on this world, and the perturbed check.
  void show_preview(const naturalization::DefineOutcome& shown) {
    for (std::size_t i = 0; i < shown.rules.size() && i < shown.previews.size(); ++i) {
      const auto& r = *shown.rules[i];
      out_ << shown.previews[i].id << ": " << r.lhs << " -> " << rhs_text(r) << "  =>  "
           << sdk::render(r.sem) << '\n';
      if (shown.previews[i].sentences.empty()) out_ << "    (reads only \"" << r.head << "\")\n";
      for (const auto& e : shown.previews[i].sentences) {
        out_ << "    \"" << e.text << "\" -> " << sdk::render(e.program) << ": ";
        if (!e.plan.error.empty()) {
          out_ << "fails here (" << e.plan.error << ")\n";
          continue;
        }
        out_ << e.plan.moves << " moves, " << e.plan.picks << " picks, " << e.plan.drops << " drops"
             << (e.plan.realizable ? "" : ", not realizable here") << '\n';
      }
    }
    if (shown.perturbations == 0)
      out_ << "Perturbed check: not run (induction.perturbed_checks = 0, or no rewriting).\n";
    else
      out_ << "Perturbed check: the body used agrees with yours on " << shown.perturbed_passed
           << " of " << shown.perturbations << " perturbed worlds.\n";
    for (const auto& f : shown.perturbed_failed) out_ << "  " << f << '\n';
  }

  void define(const std::string& head, bool preview = false) {
    if (head.empty() || sdk::tokenize(head).empty()) {
      out_ << "usage: :define HEAD (or make a query first); the head needs a word\n";
      return;
    }
    // The head is checked first: a phrase the core language already reads is not taught.
    try {
      const kernel::QueryResult h = session_.query(kernel::QueryRequest{head, 1});
      if (std::string_view(h.status) == "core") {
        const kernel::LastQuery& q = *h.query;
        out_ << "\"" << head << "\" already means "
             << sdk::render(q.parse.candidates[q.shown.at(0).index].program)
             << " in the core language; use it as it is.\n";
        return;
      }
    } catch (const std::exception&) {  // not readable as it is: a head to teach
    }
    out_ << "Defining \"" << head << "\". Enter the steps, one per line; an empty line ends, "
         << "Ctrl-C (or :cancel) abandons it.\n";
    naturalization::DefineCall definition;
    definition.head = head;
    std::string line;
    bool ended = false;  // by the empty line (not by :cancel or the end of input)
    while (read_definition_line("  ...> ", line)) {
      if (line.empty()) {
        ended = true;
        break;
      }
      kernel::QueryResult result;
      const bool ok = call([&] { result = session_.query(kernel::QueryRequest{line, kKeep}); });
      if (reader_.take_interrupt()) {
        out_ << "Definition cancelled; nothing was learned.\n";
        return;
      }
      if (!ok) continue;
      const kernel::LastQuery& q = *result.query;
      const auto& cands = q.shown;
      if (cands.empty()) {
        out_ << "  I do not understand \"" << line << "\". " << unknown_words_note(line)
             << "  Type the step again (an empty line ends the definition).\n";
        continue;
      }
      int rank = 0;
      if (cands.size() > 1) {
        out_ << "  \"" << line << "\" has " << cands.size() << " readings:\n";
        for (std::size_t i = 0; i < cands.size() && i < 9; ++i)
          out_ << "    [" << i + 1 << "] "
               << sdk::render(q.parse.candidates[cands[i].index].program) << '\n';
        std::string pick;
        while (true) {
          if (!read_definition_line("  which reading? [1] ", pick)) return;
          const auto n = pick.empty() ? std::optional<int>(1) : parse_int(pick);
          if (n && *n >= 1 && *n <= static_cast<int>(cands.size())) {
            rank = *n - 1;
            break;
          }
          out_ << "  Choose 1.." << cands.size() << " (empty: 1).\n";
        }
      }
      definition.body.push_back(line);
      definition.ranks.push_back(rank);
    }
    if (!ended) return;
    if (definition.body.empty()) {
      out_ << "Nothing defined.\n";
      return;
    }
    auto* nat = lexicon();
    if (preview) {
      definition.preview = true;
      naturalization::DefineOutcome shown;
      if (nat == nullptr || !call([&] { shown = nat->define(session_, definition); })) return;
      show_preview(shown);
      std::string answer;
      if (!read_definition_line("Store it? [y]es, n(o), or the rules to leave out (new2 ...): ",
                                answer) ||
          answer == "n" || answer == "no") {
        out_ << "Nothing defined.\n";
        return;
      }
      if (answer != "y" && answer != "yes" && !answer.empty())
        for (std::istringstream ids(answer); ids >> answer;) definition.drop.push_back(answer);
      definition.preview = false;
    }
    naturalization::DefineOutcome defined;
    if (nat == nullptr || !call([&] { defined = nat->define(session_, definition); })) return;
    if (!defined.held.empty()) {
      out_ << "Held for a researcher's approval as " << defined.held << " (" << defined.rules.size()
           << (defined.rules.size() == 1 ? " rule" : " rules")
           << "): it serves no one until approved (lexicon.moderation = hold_new).\n";
      readings_ = kernel::Json::array();
      return;
    }
    const auto& rules = defined.rules;
    out_ << "Learned " << rules.size() << (rules.size() == 1 ? " rule" : " rules") << ":\n";
    for (const auto& r : rules) out_ << rule_text(*r) << '\n';
    if (defined.generalized)  // quoted, as the protocol's "generalized" string
      out_ << "(generalized the body to: " << kernel::Json(sdk::render(defined.generalized)).dump()
           << ")\n";
    // Phrases other users rely on that now read differently (docs/naturalization.md §5).
    for (const auto& c : defined.conflicts)
      out_ << "Note: " << c.user << "'s \"" << c.phrase << "\" "
           << (c.kind == "first_reading" ? "now first reads " + c.after + " (was " +
                                               (c.before.empty() ? "nothing" : c.before) + ")"
                                         : "gains a reading (" + std::to_string(c.readings_before) +
                                               " -> " + std::to_string(c.readings_after) + ")")
           << "\n";
    // The lexicon picks up other processes' rules before each parse (docs/naturalization.md).
    out_ << "(Stored in the lexicon: other repls and sessions on the same store can use it from "
            "their next query on.)\n";
    readings_ = kernel::Json::array();
  }

  kernel::Session& session_;
  LineReader& reader_;
  std::ostream& out_;
  int page_;  // readings per page: session.k
  kernel::Json readings_ =
      kernel::Json::array();  // the last query's kept readings (empty: nothing to choose)
  int shown_ = 0;             // how many of them are on screen
  std::size_t total_ = 0;     // how many the parser found
  kernel::Json query_world_;
  std::string last_text_;
  std::vector<sdk::WorldState> undo_;
  kernel::Json trail_;        // the trace of the reading just chosen (null after the next query)
  kernel::Json trail_world_;  // the world it started from
  std::string trail_title_;
  std::optional<int> floor_;
};

}  // namespace

int run(kernel::Session& session, LineReader& reader, std::ostream& out) {
  return Repl(session, reader, out).run();
}

}  // namespace flipper::repl
