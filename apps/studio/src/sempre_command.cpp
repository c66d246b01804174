// Reading /sempre commands (see sempre_command.hpp).
#include "sempre_command.hpp"

#include <charconv>
#include <nlohmann/json.hpp>

#include "flipper/sdk/errors.hpp"

namespace flipper::studio {
namespace {

[[noreturn]] void refuse(const std::string& name, const std::string& what) {
  throw sdk::Error(sdk::codes::kBadRequest,
                   "(:" + name + " ...): " + what + " (docs/sempre.md lists the commands)");
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

// The arguments of one command: the text between its name and its closing ')'.
class Args {
 public:
  Args(std::string name, std::string_view text) : name_(std::move(name)), s_(text) {}

  bool at_end() {
    skip();
    return pos_ == s_.size();
  }
  // A JSON string literal ("..." with JSON escapes), decoded.
  std::string string(const char* what) {
    skip();
    if (pos_ >= s_.size() || s_[pos_] != '"') refuse(name_, std::string("expected ") + what);
    const std::size_t start = pos_;
    for (++pos_; pos_ < s_.size() && s_[pos_] != '"'; ++pos_)
      if (s_[pos_] == '\\') ++pos_;
    if (pos_ >= s_.size()) refuse(name_, std::string(what) + " is not closed with '\"'");
    ++pos_;
    const auto j = nlohmann::json::parse(s_.substr(start, pos_ - start), nullptr, false);
    if (j.is_discarded() || !j.is_string())
      refuse(name_, std::string(what) + " is not a JSON string literal");
    return j.get<std::string>();
  }
  std::int64_t integer(const char* what) {
    skip();
    const std::size_t start = pos_;
    while (pos_ < s_.size() && !is_space(s_[pos_])) ++pos_;
    const std::string_view t = s_.substr(start, pos_ - start);
    std::int64_t v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || ec != std::errc() || end != t.data() + t.size())
      refuse(name_, std::string("expected ") + what + ", got '" + std::string(t) + "'");
    return v;
  }
  void end() {
    if (!at_end()) refuse(name_, "unexpected text '" + std::string(s_.substr(pos_)) + "'");
  }

 private:
  void skip() {
    while (pos_ < s_.size() && is_space(s_[pos_])) ++pos_;
  }
  std::string name_;
  std::string_view s_;
  std::size_t pos_ = 0;
};

// The opening quote of the JSON string literal that ends at `close` (the index of its closing
// quote): the nearest quote before it that no backslash escapes.
std::size_t literal_start(std::string_view s, std::size_t close) {
  for (std::size_t i = close; i-- > 0;) {
    if (s[i] != '"') continue;
    std::size_t slashes = 0;
    while (slashes < i && s[i - 1 - slashes] == '\\') ++slashes;
    if (slashes % 2 == 0) return i;
  }
  return std::string_view::npos;
}

// (:def "<head as typed, unescaped>" <body as a JSON string literal>): the body is the last
// literal, found from the end, so the head may hold anything, quotes and trailing spaces too.
void read_definition(const std::string& name, std::string_view args, SempreCommand& c) {
  args = trim(args);
  if (args.size() < 2 || args.front() != '"' || args.back() != '"')
    refuse(name, "expected a quoted head and a body string");
  const std::size_t open = literal_start(args, args.size() - 1);
  if (open == std::string_view::npos || open == 0) refuse(name, "expected a body string");
  Args body(name, args.substr(open));
  c.body = body.string("the body (a JSON string)");
  std::string_view head = args.substr(0, open);
  while (!head.empty() && is_space(head.back())) head.remove_suffix(1);
  if (head.size() < 2 || head.back() != '"')
    refuse(name, "expected the head between double quotes before the body");
  c.text = std::string(head.substr(1, head.size() - 2));
}

}  // namespace

SempreCommand parse_sempre_command(std::string_view q) {
  SempreCommand c;
  const std::string_view t = trim(q);
  if (t.substr(0, 2) != "(:") {  // the original: anything else is a query
    c.kind = SempreCommand::Kind::query;
    c.name = "q";
    c.text = std::string(t);
    return c;
  }
  std::size_t p = 2;
  while (p < t.size() && !is_space(t[p]) && t[p] != ')' && t[p] != '"') ++p;
  c.name = std::string(t.substr(2, p - 2));
  if (t.back() != ')') refuse(c.name, "the command does not end with ')'");
  const std::string_view rest = t.substr(p, t.size() - 1 - p);
  using Kind = SempreCommand::Kind;
  if (c.name == "def" || c.name == "def_ret" || c.name == "def_iso") {
    c.kind = Kind::define;
    read_definition(c.name, rest, c);
    return c;
  }
  Args a(c.name, rest);
  if (c.name == "context") {
    c.kind = Kind::context;
    c.text = a.string("the world (a JSON string)");
  } else if (c.name == "q") {
    c.kind = Kind::query;
    c.text = a.string("the command text (a JSON string)");
  } else if (c.name == "accept") {
    c.kind = Kind::accept;
    c.text = a.string("the utterance (a JSON string)");
    c.formula = a.string("the accepted formula (a JSON string)");
  } else if (c.name == "reject") {
    // "(:reject "utt" )" and "(:reject "utt" "formula" ...)": the formulas are not used.
    c.kind = Kind::reject;
    c.text = a.string("the utterance (a JSON string)");
    while (!a.at_end()) (void)a.string("a formula (a JSON string)");
  } else if (c.name == "dictionary") {
    c.kind = Kind::dictionary;
  } else if (c.name == "delete") {
    c.kind = Kind::delete_rule;
    c.index = a.integer("the rule's index (an integer)");
  } else {
    throw sdk::Error(sdk::codes::kBadRequest,
                     "unknown command '(:" + c.name +
                         "'; /sempre answers :context, :q, :accept, :reject, :def, :def_ret, "
                         ":def_iso, :dictionary and :delete");
  }
  a.end();
  return c;
}

std::vector<SempreStep> parse_sempre_body(std::string_view json) {
  const auto j = nlohmann::json::parse(json, nullptr, false);
  auto bad = [] {
    throw sdk::Error(sdk::codes::kBadRequest,
                     "a definition's body must be a JSON list of [utterance, formula] pairs");
  };
  if (j.is_discarded() || !j.is_array()) bad();
  std::vector<SempreStep> steps;
  for (const auto& pair : j) {
    if (!pair.is_array() || pair.size() != 2 || !pair[0].is_string() || !pair[1].is_string()) bad();
    steps.push_back({pair[0].get<std::string>(), pair[1].get<std::string>()});
  }
  return steps;
}

}  // namespace flipper::studio
