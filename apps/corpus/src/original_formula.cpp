// The original's formulas -> canonical text (see original_formula.hpp).
#include "flipper/corpus/original_formula.hpp"

#include "flipper/sdk/canonical.hpp"

#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "flipper/sdk/errors.hpp"

namespace flipper::corpus {
namespace {

constexpr int kMaxDepth = 256;  // as the canonical reader (core-language §7)

struct Sexp {
  std::string atom;  ///< empty for a list
  std::vector<Sexp> kids;
  bool list = false;
};

[[noreturn]] void fail(const std::string& what) {
  throw sdk::Error(sdk::codes::kBadProgram, "cannot read the original formula: " + what);
}

class Reader {
 public:
  explicit Reader(std::string_view text) : s_(text) {}

  Sexp read_all() {
    Sexp e = read(0);
    skip_space();
    if (pos_ != s_.size()) fail("unexpected text after the formula at position " + at());
    return e;
  }

 private:
  std::string at() const { return std::to_string(pos_ + 1); }
  void skip_space() {
    while (pos_ < s_.size() &&
           (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\n' || s_[pos_] == '\r'))
      ++pos_;
  }
  Sexp read(int depth) {
    if (depth > kMaxDepth) fail("nested deeper than " + std::to_string(kMaxDepth) + " levels");
    skip_space();
    if (pos_ >= s_.size()) fail("the formula ends too early");
    Sexp e;
    if (s_[pos_] == '(') {
      ++pos_;
      e.list = true;
      for (;;) {
        skip_space();
        if (pos_ >= s_.size()) fail("a '(' is not closed");
        if (s_[pos_] == ')') {
          ++pos_;
          return e;
        }
        e.kids.push_back(read(depth + 1));
      }
    }
    if (s_[pos_] == ')') fail("unexpected ')' at position " + at());
    const std::size_t start = pos_;
    while (pos_ < s_.size() && s_[pos_] != '(' && s_[pos_] != ')' && s_[pos_] != ' ' &&
           s_[pos_] != '\t' && s_[pos_] != '\n' && s_[pos_] != '\r')
      ++pos_;
    e.atom = std::string(s_.substr(start, pos_ - start));
    return e;
  }

  std::string_view s_;
  std::size_t pos_ = 0;
};

std::string show(const Sexp& e) {
  if (!e.list) return e.atom;
  std::string out = "(";
  for (std::size_t i = 0; i < e.kids.size(); ++i) out += (i ? " " : "") + show(e.kids[i]);
  return out + ")";
}

// The first atom of a list form ("" for an atom or a form starting with a list).
const std::string& head(const Sexp& e) {
  static const std::string none;
  return e.list && !e.kids.empty() && !e.kids[0].list ? e.kids[0].atom : none;
}

// "(call name args...)" -> name, or "" for other forms.
const std::string& called(const Sexp& e) {
  static const std::string none;
  return head(e) == "call" && e.kids.size() >= 2 && !e.kids[1].list ? e.kids[1].atom : none;
}

void arity(const Sexp& e, std::size_t n) {
  if (e.kids.size() != n) fail("'" + show(e) + "' has the wrong number of arguments");
}

std::string braced(const std::string& a, const char* op, const std::string& b) {
  return "{" + a + op + b + "}";
}

// (and A B), (or A B) and, where the sort has it, (not A), over parts of the same sort read by
// `part`; nullopt for any other form.
std::optional<std::string> connective(const Sexp& e, std::string (*part)(const Sexp&),
                                      bool with_not) {
  const std::string& h = head(e);
  if (h == "and" || h == "or") {
    arity(e, 3);
    return braced(part(e.kids[1]), h == "and" ? " and " : " or ", part(e.kids[2]));
  }
  if (with_not && h == "not") {
    arity(e, 2);
    return "{not " + part(e.kids[1]) + "}";
  }
  return std::nullopt;
}

std::string number(const Sexp& e);
std::string action(const Sexp& e);
std::string location(const Sexp& e);
std::string item(const Sexp& e);

std::string number(const Sexp& e) {
  if (head(e) == "number") {
    arity(e, 2);
    const std::string& t = e.kids[1].atom;
    double v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v))
      fail("'" + t + "' is not a number of the core language");
    if (v == std::floor(v) && std::fabs(v) < 1e15) return std::to_string(static_cast<long long>(v));
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
  }
  if (head(e) == "+" || head(e) == "-") {
    arity(e, 3);
    return braced(number(e.kids[1]), head(e) == "+" ? " + " : " - ", number(e.kids[2]));
  }
  fail("'" + show(e) + "' is not a number");
}

// A filter over items: (items?property red), (items?color red) [February 2018], and/or/not.
std::string filter(const Sexp& e) {
  const std::string& h = head(e);
  if (h == "items?property" || h == "items?color" || h == "items?shape") {
    arity(e, 2);
    return "{is " + e.kids[1].atom + "}";
  }
  if (auto c = connective(e, filter, true)) return *c;
  fail("'" + show(e) + "' is not an item filter");
}

// `item ` (every item, printed with its trailing space as render does) or `item {filter}`.
std::string item(const Sexp& e) {
  if (called(e) == "allItems") {
    arity(e, 2);
    return "item ";
  }
  return "item " + filter(e);
}

// The elements of a list built with combineAreas / combineCollections / createAreaListFromArea.
void list_elements(const Sexp& e, std::vector<std::string>& out) {
  const std::string& f = called(e);
  if (f == "combineAreas" || f == "combineCollections") {
    arity(e, 4);
    list_elements(e.kids[2], out);
    list_elements(e.kids[3], out);
  } else if (f == "createAreaListFromArea") {
    arity(e, 3);
    out.push_back(location(e.kids[2]));
  } else {
    out.push_back(location(e));
  }
}

// Points, areas and collections (their canonical text does not depend on the sort).
std::string location(const Sexp& e) {
  if (!e.list) {
    if (e.atom == "world") return "world";
    if (e.atom == "all_rooms") return "rooms";
    if (e.atom.rfind("room", 0) == 0 && e.atom.size() > 4) return e.atom;
    fail("'" + e.atom + "' is not a location");
  }
  if (auto c = connective(e, location, false)) return *c;
  const std::string& f = called(e);
  if (f == "makePoint") {
    arity(e, 4);
    return "[" + number(e.kids[2]) + "," + number(e.kids[3]) + "]";
  }
  if (f == "getSelectedPoint" || f == "getSelectedArea" || f == "getRobotLocation") {
    arity(e, 2);
    return f == "getSelectedPoint" ? "point" : f == "getSelectedArea" ? "area" : "current";
  }
  if (f == "makeArray") {
    arity(e, 3);
    std::vector<std::string> elements;
    list_elements(e.kids[2], elements);
    std::string out = "{[";
    for (std::size_t i = 0; i < elements.size(); ++i) out += (i ? ", " : "") + elements[i];
    return out + "]}";
  }
  if (f == "filterArea" || f == "areasFromItems") {
    arity(e, 4);
    return braced(location(e.kids[2]), " containing ", item(e.kids[3]));
  }
  if (f == "setOfLocationsDifference") {
    arity(e, 4);
    return braced(location(e.kids[2]), " minus ", location(e.kids[3]));
  }
  if (f == "getAreaWithCorners") {
    arity(e, 4);
    return "{area with corners " + location(e.kids[2]) + " and " + location(e.kids[3]) + "}";
  }
  fail("'" + show(e) + "' is not a location");
}

// The item of `{$1 item ...}` without the trailing space of an unfiltered one when it ends the
// condition `{item at X}`.
std::string item_at(const Sexp& items, const Sexp& where) {
  std::string i = item(items);
  if (i.back() == ' ') i.pop_back();
  return "{" + i + " at " + location(where) + "}";
}

std::string condition(const Sexp& e) {
  const std::string& h = head(e);
  if (auto c = connective(e, condition, true)) return *c;
  if (h == ":realizable") {
    arity(e, 2);
    return "{possible " + action(e.kids[1]) + "}";
  }
  const std::string& f = called(e);
  if (f == "robotHas") {
    arity(e, 3);
    return "{robot has " + item(e.kids[2]) + "}";
  }
  if (f == "robotAt") {
    arity(e, 3);
    return "{robot at " + location(e.kids[2]) + "}";
  }
  if (f == "itemAt") {
    arity(e, 4);
    return item_at(e.kids[2], e.kids[3]);
  }
  fail("'" + show(e) + "' is not a condition");
}

// (: visit P [AVOID]), (: visitArea A [AVOID]), (: visitAreaCollections C [AVOID]).
std::string visit(const Sexp& e) {
  if (e.kids.size() != 3 && e.kids.size() != 4) arity(e, 3);
  std::string out = "{visit " + location(e.kids[2]);
  if (e.kids.size() == 4) out += " while avoiding " + location(e.kids[3]);
  return out + "}";
}

// (: itemActionHandler pick|drop (call setLimit (number 1|-1) ITEM)).
std::string item_action(const Sexp& e) {
  arity(e, 4);
  const std::string& act = e.kids[2].atom;
  if (act != "pick" && act != "drop") fail("'" + show(e) + "' is neither pick nor drop");
  const Sexp& limited = e.kids[3];
  if (called(limited) != "setLimit") fail("'" + show(limited) + "' is not a counted item");
  arity(limited, 4);
  const std::string count = number(limited.kids[2]);
  if (count != "1" && count != "-1")
    fail("'" + show(limited) + "': the core language picks or drops one item or every item");
  return "{" + act + (count == "-1" ? " every " : " ") + item(limited.kids[3]) + "}";
}

std::string action(const Sexp& e) {
  const std::string& h = head(e);
  if (h == ":") {
    if (e.kids.size() < 2 || e.kids[1].list) fail("'" + show(e) + "' names no action");
    const std::string& a = e.kids[1].atom;
    if (a == "move") {
      arity(e, 3);
      return "{move " + e.kids[2].atom + "}";
    }
    if (a == "visit" || a == "visitArea" || a == "visitAreaCollections") return visit(e);
    if (a == "itemActionHandler") return item_action(e);
    fail("unknown action '" + a + "'");
  }
  if (h == ":s") {
    if (e.kids.size() < 2) arity(e, 2);
    std::string out = "{";
    for (std::size_t i = 1; i < e.kids.size(); ++i) out += (i > 1 ? ";" : "") + action(e.kids[i]);
    return out + "}";
  }
  if (h == ":foreach") {
    arity(e, 4);
    const std::string& var = e.kids[1].atom;
    if (var != "point" && var != "area")
      fail("'" + show(e) + "' loops over neither points nor areas");
    return "{foreach " + var + " in " + location(e.kids[2]) + " " + action(e.kids[3]) + "}";
  }
  if (h == ":loop") {
    arity(e, 3);
    return "{repeat " + number(e.kids[1]) + " times " + action(e.kids[2]) + "}";
  }
  if (h == ":if" || h == ":while") {
    arity(e, 3);
    return "{" + h.substr(1) + " " + condition(e.kids[1]) + " " + action(e.kids[2]) + "}";
  }
  if (h == ":strict") {
    arity(e, 2);
    return "{strict " + action(e.kids[1]) + "}";
  }
  fail("'" + show(e) + "' is not an action");
}

}  // namespace

bool is_original_formula(std::string_view text) {
  const auto p = text.find_first_not_of(" \t\r\n");
  return p != std::string_view::npos && text[p] == '(';
}

std::string original_formula_to_canonical(std::string_view formula) {
  return action(Reader(formula).read_all());
}

sdk::Program read_formula(std::string_view formula) {
  try {
    return sdk::read_canonical(is_original_formula(formula) ? original_formula_to_canonical(formula)
                                                            : std::string(formula));
  } catch (const sdk::Error& e) {
    throw sdk::Error(e.code(),
                     "the formula '" + std::string(formula) + "' does not read: " + e.what());
  }
}

}  // namespace flipper::corpus
