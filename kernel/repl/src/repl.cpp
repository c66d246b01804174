// The interactive loop: utterances become queries; a number accepts, `r` rejects; `:` commands.
#include "flipper/kernel/repl.hpp"

#include <charconv>
#include <ostream>

namespace flipper::kernel::repl {
namespace {

const char* kHelp =
    "Type an utterance (e.g. `visit room1; pick item is red`) to see its interpretations.\n"
    "  N              choose interpretation N (the robot does it)\n"
    "  r              reject all shown interpretations\n"
    "  :define HEAD   teach HEAD (default: the last utterance); then one body line per\n"
    "                 line, each something Flipper understands, ending with an empty line\n"
    "  :world FILE    load a world file        :user NAME   set the current user\n"
    "  :rules         list the rules you can use\n"
    "  :map           show the world           :help        this text\n"
    "  :quit          leave\n";

std::string trim(const std::string& s) {
  auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

// "r1  zig zag  =>  {...}  (by ana, used 2x)"; tolerant of missing fields.
std::string describe_rule(const Json& r) {
  std::string rhs;
  for (const auto& t : r.value("rhs", Json::array()))
    rhs += (rhs.empty() ? "" : " ") + (t.is_string() ? t.get<std::string>() : t.dump());
  std::string line = "  " + r.value("id", std::string("?")) + "  " + r.value("lhs", std::string()) +
                     " -> " + rhs + "  =>  " + r.value("semantics", std::string());
  line += "  (by " + r.value("author", std::string("?"));
  if (r.contains("uses") && r["uses"].is_number()) line += ", used " + r["uses"].dump() + "x";
  return line + ")\n";
}

class Repl {
 public:
  Repl(Session& s, LineReader& r, std::ostream& o) : session_(s), reader_(r), out_(o) {}

  int run() {
    out_ << "Flipper -- precise but natural robot tasks. :help for commands.\n";
    show_map();
    std::string line;
    while (reader_.read("flipper> ", line)) {
      line = trim(line);
      if (line.empty()) continue;
      if (line[0] == ':') {
        if (!command(line)) break;
      } else if (shown_ > 0 && choice(line)) {
      } else if (shown_ > 0 && line == "r") {
        out_ << "Rejected. Rephrase it, or teach it with :define.\n";
        shown_ = 0;
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
  Json call(const Json& request) {
    Json answer = session_.handle(request);
    if (!answer.value("ok", false)) {
      const Json& e = answer["error"];
      out_ << "error (" << e.value("code", std::string())
           << "): " << e.value("message", std::string()) << '\n';
    }
    return answer;
  }

  void show_map() {
    Json a = call(Json{{"op", "state"}});
    if (a.value("ok", false)) out_ << render_map(a["world"]);
  }

  void query(const std::string& text) {
    last_text_ = text;
    shown_ = 0;
    Json a = call(Json{{"op", "query"}, {"text", text}});
    if (!a.value("ok", false)) return;
    const Json& cands = a["candidates"];
    if (cands.empty()) {
      out_
          << "I did not understand that. Teach me with `:define` (then the steps, one per line).\n";
      return;
    }
    out_ << "Interpretations (" << a.value("status", std::string()) << "):\n";
    int n = 0;
    for (const auto& c : cands) out_ << describe_candidate(c, ++n);
    shown_ = n;
    out_ << "Choose 1.." << n << ", or r to reject all.\n";
  }

  bool choice(const std::string& line) {
    int n = 0;
    auto [end, ec] = std::from_chars(line.data(), line.data() + line.size(), n);
    if (ec != std::errc() || end != line.data() + line.size()) return false;
    if (n < 1 || n > shown_) {
      out_ << "Choose a number from 1 to " << shown_ << ".\n";
      return true;
    }
    Json a = call(Json{{"op", "accept"}, {"rank", n - 1}});
    if (!a.value("ok", false)) return true;
    shown_ = 0;
    std::size_t steps = 0;
    for (const auto& s : a["trace"]) steps += s.value("act", std::string()) == "move";
    out_ << "Done: " << steps << " steps.\n";
    for (const auto& w : a["warnings"]) out_ << "warning: " << w.get<std::string>() << '\n';
    out_ << render_map(a["world"]);
    return true;
  }

  bool command(const std::string& line) {
    auto space = line.find(' ');
    std::string cmd = line.substr(0, space);
    std::string arg = space == std::string::npos ? "" : trim(line.substr(space + 1));
    if (cmd == ":quit" || cmd == ":q" || cmd == ":exit") return false;
    if (cmd == ":help" || cmd == ":h") {
      out_ << kHelp;
    } else if (cmd == ":map" || cmd == ":state") {
      show_map();
    } else if (cmd == ":world") {
      if (arg.empty()) {
        out_ << "usage: :world FILE\n";
        return true;
      }
      Json a = call(Json{{"op", "world"}, {"file", arg}});
      if (a.value("ok", false)) {
        shown_ = 0;
        out_ << render_map(a["world"]);
      }
    } else if (cmd == ":user") {
      if (arg.empty()) {
        out_ << "usage: :user NAME\n";
        return true;
      }
      Json a = call(Json{{"op", "user"}, {"name", arg}});
      if (a.value("ok", false)) out_ << "You are " << a["name"].get<std::string>() << ".\n";
    } else if (cmd == ":rules") {
      Json a = call(Json{{"op", "rules"}});
      if (a.value("ok", false)) {
        const Json rules = a.value("rules", Json::array());
        if (rules.empty()) out_ << "No rules.\n";
        for (const auto& r : rules) out_ << describe_rule(r);
      }
    } else if (cmd == ":define") {
      define(arg.empty() ? last_text_ : arg);
    } else {
      out_ << "Unknown command " << cmd << ". :help lists the commands.\n";
    }
    return true;
  }

  void define(const std::string& head) {
    if (head.empty()) {
      out_ << "usage: :define HEAD (or make a query first)\n";
      return;
    }
    out_ << "Defining \"" << head << "\". Enter the steps, one per line; an empty line ends.\n";
    Json body = Json::array();
    std::string line;
    while (reader_.read("  ...> ", line) && !trim(line).empty()) body.push_back(trim(line));
    if (body.empty()) {
      out_ << "Nothing defined.\n";
      return;
    }
    Json a = call(Json{{"op", "define"}, {"head", head}, {"body", body}});
    if (!a.value("ok", false)) return;
    const Json rules = a.value("rules", Json::array());
    out_ << "Learned " << rules.size() << (rules.size() == 1 ? " rule" : " rules") << ":\n";
    for (const auto& r : rules) {
      out_ << "  " << r.value("lhs", std::string()) << " ->";
      for (const auto& t : r.value("rhs", Json::array())) out_ << ' ' << t.get<std::string>();
      out_ << "  =>  " << r.value("semantics", std::string()) << '\n';
    }
    if (a.contains("generalized") && !a["generalized"].is_null())
      out_ << "(generalized the body to: " << a["generalized"].dump() << ")\n";
    shown_ = 0;
  }

  Session& session_;
  LineReader& reader_;
  std::ostream& out_;
  int shown_ = 0;
  std::string last_text_;
};

}  // namespace

int run(Session& session, LineReader& reader, std::ostream& out) {
  return Repl(session, reader, out).run();
}

}  // namespace flipper::kernel::repl
