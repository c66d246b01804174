// Lexer (core-language §2), canonical rendering (§7) and the reader of canonical text.
//
// The reader is a small recursive descent over tokens that decides sorts bottom-up: every term
// is read without knowing what it must be, and its sort picks the node kind where the text is
// shared between sorts (`{A or B}` on conditions, areas, collections and filters; `visit X` on
// points, areas and collections; `[...]` as a point or a list). This keeps the reader one
// function per token shape instead of one per sort.
#include "flipper/sdk/canonical.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <string>

#include "flipper/sdk/errors.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}
bool is_letter(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}
bool is_digit(char c) {
  return c >= '0' && c <= '9';
}
bool is_separate(char c) {
  switch (c) {
    case ',':
    case '?':
    case '\'':
    case '"':
    case '[':
    case ']':
    case ';':
    case '{':
    case '}':
    case '+':
    case '=':
    case '<':
    case '>':
      return true;
    default:
      return false;
  }
}
char lower(char c) {
  return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
}

struct Token {
  std::string text;
  std::size_t pos;  // byte offset in the input
};

// §2 in one pass. Periods and hyphens are judged against the original input (rules 3 and 4).
std::vector<Token> lex(std::string_view in) {
  std::vector<Token> out;
  const std::size_t n = in.size();
  std::string cur;
  std::size_t cur_pos = 0;
  auto flush = [&] {
    if (!cur.empty()) out.push_back({std::move(cur), cur_pos});
    cur.clear();
  };
  auto boundary = [&](std::size_t j) { return j >= n || is_space(in[j]); };
  for (std::size_t i = 0; i < n; ++i) {
    const char c = in[i];
    if (is_space(c)) {
      flush();
      continue;
    }
    if (is_separate(c)) {
      flush();
      if ((c == '<' || c == '>') && i + 1 < n && in[i + 1] == '=') {
        out.push_back({std::string{c, '='}, i});
        ++i;
      } else {
        out.push_back({std::string(1, c), i});
      }
      continue;
    }
    if (c == '-' && i + 1 < n && is_letter(in[i + 1])) {  // rule 3: "pick-up" = "pick up"
      flush();
      continue;
    }
    if (c == '.' && ((i == 0 || is_space(in[i - 1])) || boundary(i + 1))) {  // rule 4
      flush();
      out.push_back({".", i});
      continue;
    }
    if (cur.empty()) cur_pos = i;
    cur.push_back(lower(c));
  }
  flush();
  return out;
}

constexpr std::array<const char*, 11> kNumberWords = {
    "zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten"};

[[noreturn]] void fail_at(std::size_t pos, const std::string& what) {
  throw Error(codes::kBadProgram, "at position " + std::to_string(pos) + ": " + what);
}

// ----------------------------------------------------------------------------------------------
// Rendering

void render_number(double v, std::string& out) {
  if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15) {
    out += std::to_string(static_cast<long long>(v));
    return;
  }
  // The shortest fixed form that reads back: the reader takes -?digits[.digits] only, and the
  // shortest form of all would write 1e-04 or 5e-76 (docs/core-language.md). A double's fixed form
  // is at most 1 + 309 digits before the point and 1 + 324 after it with its sign.
  char buf[400];
  auto res = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed);
  out.append(buf, res.ptr);
}

void render_to(const Program& p, std::string& out);

void render_item(const Node& n, std::string& out) {  // Item: "item " / "item {is red}"
  out += "item ";
  if (!n.kids.empty()) render_to(n.kids[0], out);
}

void binary(const Node& n, const char* op, std::string& out) {
  out += '{';
  render_to(n.kids[0], out);
  out += op;
  render_to(n.kids[1], out);
  out += '}';
}

void keyword_then(const char* head, const Node& n, std::string& out) {  // "{head kid0 kid1...}"
  out += '{';
  out += head;
  for (std::size_t i = 0; i < n.kids.size(); ++i) {
    if (i > 0) out += ' ';
    render_to(n.kids[i], out);
  }
  out += '}';
}

void render_list(const Node& n, std::string& out) {  // "{[a, b]}"
  out += "{[";
  for (std::size_t i = 0; i < n.kids.size(); ++i) {
    if (i > 0) out += ", ";
    render_to(n.kids[i], out);
  }
  out += "]}";
}

void render_visit(const Node& n, std::string& out) {
  out += "{visit ";
  render_to(n.kids[0], out);
  if (n.kids.size() > 1) {
    out += " while avoiding ";
    render_to(n.kids[1], out);
  }
  out += '}';
}

void render_to(const Program& p, std::string& out) {
  if (!p) throw Error(codes::kBadProgram, "render: null program");
  const Node& n = *p;
  switch (n.kind) {
    case Kind::Seq:
      out += '{';
      for (std::size_t i = 0; i < n.kids.size(); ++i) {
        if (i > 0) out += ';';
        render_to(n.kids[i], out);
      }
      out += '}';
      return;
    case Kind::Strict:
      return keyword_then("strict ", n, out);
    case Kind::Move:
      return keyword_then("move ", n, out);
    case Kind::VisitPoint:
    case Kind::VisitArea:
    case Kind::VisitCollection:
      return render_visit(n, out);
    case Kind::Pick:
      return keyword_then("pick ", n, out);
    case Kind::Drop:
      return keyword_then("drop ", n, out);
    case Kind::ForeachPoint:
      return keyword_then("foreach point in ", n, out);
    case Kind::ForeachArea:
      return keyword_then("foreach area in ", n, out);
    case Kind::Repeat:
      out += "{repeat ";
      render_to(n.kids[0], out);
      out += " times ";
      render_to(n.kids[1], out);
      out += '}';
      return;
    case Kind::If:
      return keyword_then("if ", n, out);
    case Kind::While:
      return keyword_then("while ", n, out);
    case Kind::CondAnd:
    case Kind::AreaAnd:
    case Kind::CollAnd:
    case Kind::FilterAnd:
      return binary(n, " and ", out);
    case Kind::CondOr:
    case Kind::AreaOr:
    case Kind::CollOr:
    case Kind::FilterOr:
      return binary(n, " or ", out);
    case Kind::AreaMinus:
    case Kind::CollMinus:
      return binary(n, " minus ", out);
    case Kind::AreaContaining:
    case Kind::CollContaining:
      return binary(n, " containing ", out);
    case Kind::CondNot:
    case Kind::FilterNot:
      return keyword_then("not ", n, out);
    case Kind::ItemAtPoint:
    case Kind::ItemAtArea: {
      // `{item at room1}` / `{item {is red} at room1}` (the original printed this wrongly).
      out += '{';
      std::string item;
      render_to(n.kids[0], item);
      if (!item.empty() && item.back() == ' ') item.pop_back();
      out += item;
      out += " at ";
      render_to(n.kids[1], out);
      out += '}';
      return;
    }
    case Kind::RobotHas:
      return keyword_then("robot has ", n, out);
    case Kind::RobotAtPoint:
    case Kind::RobotAtArea:
      return keyword_then("robot at ", n, out);
    case Kind::Possible:
      return keyword_then("possible ", n, out);
    case Kind::PointXY:
      out += '[';
      for (std::size_t i = 0; i < n.kids.size(); ++i) {
        if (i > 0) out += ',';
        render_to(n.kids[i], out);
      }
      out += ']';
      return;
    case Kind::Current:
      out += "current";
      return;
    case Kind::PointVar:
      out += "point";
      return;
    case Kind::World:
      out += "world";
      return;
    case Kind::AreaVar:
      out += "area";
      return;
    case Kind::Rooms:
      out += "rooms";
      return;
    case Kind::Room:
    case Kind::Direction:
    case Kind::Color:
    case Kind::Shape:
      out += n.text;
      return;
    case Kind::PointList:
    case Kind::AreaList:
      return render_list(n, out);
    case Kind::Corners:
      out += "{area with corners ";
      render_to(n.kids[0], out);
      out += " and ";
      render_to(n.kids[1], out);
      out += '}';
      return;
    case Kind::Item:
      return render_item(n, out);
    case Kind::Every:
      out += "every ";
      render_to(n.kids[0], out);
      return;
    case Kind::FilterIs:
      return keyword_then("is ", n, out);
    case Kind::Num:
      render_number(n.number, out);
      return;
    case Kind::Add:
      return binary(n, " + ", out);
    case Kind::Sub:
      return binary(n, " - ", out);
    case Kind::Hole:
      out += '$' + std::to_string(n.index + 1);
      return;
    case Kind::ItemAct:
      out += n.text;
      return;
    case Kind::ItemAction:
      // Same text as Pick/Drop: `{pick item }`, or `{$1 item }` in a template.
      out += '{';
      render_to(n.kids[0], out);
      out += ' ';
      render_to(n.kids[1], out);
      out += '}';
      return;
  }
}

// ----------------------------------------------------------------------------------------------
// Reading

bool is_shape_word(const std::string& w) {
  return w == "triangle" || w == "circle" || w == "square";
}
// Direction words are the world's business (a 3-D world adds `ascend`/`descend`; the grammar
// takes them from config), so canonical text accepts any word of letters after `move`.
bool is_direction_word(const std::string& w) {
  if (w.empty()) return false;
  for (char c : w)
    if (c < 'a' || c > 'z') return false;
  return true;
}
bool is_room_name(const std::string& w) {
  if (w.size() < 5 || w.compare(0, 4, "room") != 0) return false;
  for (std::size_t i = 4; i < w.size(); ++i)
    if (!is_digit(w[i])) return false;
  return true;
}

class Reader {
 public:
  Reader(std::string_view text, const std::vector<Sort>* holes)
      : tokens_(lex(text)), end_pos_(text.size()), holes_(holes) {}

  Program read(Sort sort) {
    // A word sort is just the word: `red` as a Color, `up` as a Direction (templates of induced
    // rules such as `$Color -> crimson => red` are stored this way).
    if ((sort == Sort::Color || sort == Sort::Shape || sort == Sort::Direction) &&
        tokens_.size() == 1 && is_direction_word(tokens_[0].text)) {
      const Kind kind = sort == Sort::Color   ? Kind::Color
                        : sort == Sort::Shape ? Kind::Shape
                                              : Kind::Direction;
      return make_word(kind, tokens_[pos_++].text);
    }
    Program p = term();
    if (pos_ < tokens_.size()) fail("unexpected '" + tokens_[pos_].text + "' after the end");
    if (!fits(sort, p->sort))
      fail_at(0, std::string("expected ") + sort_name(sort) + ", got " + sort_name(p->sort));
    return p;
  }

 private:
  std::vector<Token> tokens_;
  std::size_t end_pos_;
  const std::vector<Sort>* holes_;
  std::size_t pos_ = 0;
  std::size_t depth_ = 0;  // terms being read, one inside the other

  // Reading recurses once per nested term; a bound keeps hostile text ({ x thousands, found by
  // fuzz_canonical_text) from overflowing the stack (docs/core-language.md, canonical text).
  static constexpr std::size_t kMaxNesting = 256;
  struct Nest {
    explicit Nest(Reader& r) : r_(r) {
      if (++r_.depth_ > kMaxNesting)
        r_.fail("nested deeper than " + std::to_string(kMaxNesting) + " levels");
    }
    ~Nest() { --r_.depth_; }
    Nest(const Nest&) = delete;
    Nest& operator=(const Nest&) = delete;
    Reader& r_;
  };

  static bool fits(Sort expected, Sort actual) { return sort_fits(expected, actual); }
  std::size_t here() const { return pos_ < tokens_.size() ? tokens_[pos_].pos : end_pos_; }
  [[noreturn]] void fail(const std::string& what) const { fail_at(here(), what); }
  const std::string* peek(std::size_t ahead = 0) const {
    return pos_ + ahead < tokens_.size() ? &tokens_[pos_ + ahead].text : nullptr;
  }
  bool at(const char* t, std::size_t ahead = 0) const {
    const std::string* s = peek(ahead);
    return s != nullptr && *s == t;
  }
  bool accept(const char* t) {
    if (!at(t)) return false;
    ++pos_;
    return true;
  }
  void expect(const char* t) {
    if (!accept(t)) fail(std::string("expected '") + t + "'" + found());
  }
  std::string found() const {
    return pos_ < tokens_.size() ? ", found '" + tokens_[pos_].text + "'" : ", found the end";
  }
  std::string word() {
    if (pos_ >= tokens_.size()) fail("unexpected end");
    return tokens_[pos_++].text;
  }

  // make() with the position of the construct in its error message.
  Program build(std::size_t start, Kind kind, std::vector<Program> kids) {
    try {
      return make(kind, std::move(kids));
    } catch (const Error& e) {
      fail_at(start, e.what());
    }
  }
  Program expect_sort(std::size_t start, Program p, Sort s, const char* what) {
    if (!fits(s, p->sort))
      fail_at(start,
              std::string(what) + " must be " + sort_name(s) + ", got " + sort_name(p->sort));
    return p;
  }
  Program term_of(Sort s, const char* what) {
    const std::size_t start = here();
    return expect_sort(start, term(), s, what);
  }

  // An unbraced term: a number, a hole, a word, a list or point `[...]`, an item, or `{...}`.
  Program term() {
    const Nest nest(*this);
    const std::size_t start = here();
    if (pos_ >= tokens_.size()) fail("unexpected end");
    const std::string& t = tokens_[pos_].text;
    if (t == "{") return braced();
    if (t == "[") return bracketed();
    if (t[0] == '$') return hole();
    if (auto v = number_value(t)) {
      ++pos_;
      return make_num(*v);
    }
    if (t == "item") return item();
    if (t == "every") {
      ++pos_;
      return build(start, Kind::Every, {term_of(Sort::Item, "the operand of 'every'")});
    }
    if (t == "current") return leaf(Kind::Current);
    if (t == "point") return leaf(Kind::PointVar);
    if (t == "world") return leaf(Kind::World);
    if (t == "area") return leaf(Kind::AreaVar);
    if (t == "rooms") return leaf(Kind::Rooms);
    if (is_room_name(t)) {
      ++pos_;
      return make_word(Kind::Room, t);
    }
    if (t == "pick" || t == "drop") {  // a bare verb: the template of `$ItemAct -> pick`
      ++pos_;
      return make_word(Kind::ItemAct, t);
    }
    fail("unexpected '" + t + "'");
  }

  Program leaf(Kind k) {
    ++pos_;
    return make(k);
  }

  Program hole() {
    const std::size_t start = here();
    const std::string t = word();
    int index = 0;
    auto res = std::from_chars(t.data() + 1, t.data() + t.size(), index);
    if (res.ec != std::errc() || res.ptr != t.data() + t.size() || index < 1)
      fail_at(start, "bad hole '" + t + "'");
    if (holes_ == nullptr) fail_at(start, "hole '" + t + "' in a program that is not a template");
    if (static_cast<std::size_t>(index) > holes_->size())
      fail_at(start,
              "hole '" + t + "' but the template has " + std::to_string(holes_->size()) + " holes");
    return make_hole(index - 1, (*holes_)[static_cast<std::size_t>(index - 1)]);
  }

  bool is_hole_of(Sort s) const {
    const std::string* t = peek();
    if (t == nullptr || t->size() < 2 || (*t)[0] != '$' || holes_ == nullptr) return false;
    int index = 0;
    auto res = std::from_chars(t->data() + 1, t->data() + t->size(), index);
    return res.ec == std::errc() && index >= 1 &&
           static_cast<std::size_t>(index) <= holes_->size() &&
           (*holes_)[static_cast<std::size_t>(index - 1)] == s;
  }

  Program item() {
    const std::size_t start = here();
    expect("item");
    if (at("{") || is_hole_of(Sort::Filter))
      return build(start, Kind::Item, {term_of(Sort::Filter, "an item's filter")});
    return make(Kind::Item);
  }

  // `[n, n]` (a point) or `[p, ...]` / `[a, ...]` (a list, which render braces).
  Program bracketed() {
    const std::size_t start = here();
    expect("[");
    std::vector<Program> elems;
    elems.push_back(term());
    while (accept(",")) elems.push_back(term());
    expect("]");
    switch (elems[0]->sort) {
      case Sort::Number:
        return build(start, Kind::PointXY, std::move(elems));
      case Sort::Point:
        return build(start, Kind::PointList, std::move(elems));
      case Sort::Area:
        return build(start, Kind::AreaList, std::move(elems));
      default:
        fail_at(start, std::string("a list of ") + sort_name(elems[0]->sort) +
                           " (expected numbers, points or areas)");
    }
  }

  Program statement(const char* what) { return term_of(Sort::Action, what); }

  // `{...}`: a keyword construct, or a term followed by `;`, an operator, or `}`.
  Program braced() {
    const std::size_t start = here();
    expect("{");
    Program p = braced_body(start);
    expect("}");
    return p;
  }

  Program braced_body(std::size_t start) {
    const std::string* t = peek();
    if (t == nullptr) fail("unexpected end");
    const std::string& w = *t;
    if (w == "strict") {
      ++pos_;
      return build(start, Kind::Strict, {statement("the operand of 'strict'")});
    }
    if (w == "possible") {
      ++pos_;
      return build(start, Kind::Possible, {statement("the operand of 'possible'")});
    }
    if (w == "move") {
      ++pos_;
      if (is_hole_of(Sort::Direction)) return build(start, Kind::Move, {hole()});
      const std::size_t dpos = here();
      std::string d = word();
      if (!is_direction_word(d)) fail_at(dpos, "'" + d + "' is not a direction");
      return build(start, Kind::Move, {make_word(Kind::Direction, d)});
    }
    if (w == "visit") return visit(start);
    if (is_hole_of(Sort::ItemAct)) {  // `{$1 $2}`: a template whose verb is a hole
      Program verb = hole();
      Program what = term_of(Sort::CountedItem, "the object of pick/drop");
      return build(start, Kind::ItemAction, {verb, what});
    }
    if (w == "pick" || w == "drop") {
      ++pos_;
      Program what = term_of(Sort::CountedItem, "the object of pick/drop");
      return build(start, w == "pick" ? Kind::Pick : Kind::Drop, {what});
    }
    if (w == "foreach") {
      ++pos_;
      if (accept("point")) {
        expect("in");
        Program dom = term_of(Sort::Area, "the domain of 'foreach point'");
        return build(start, Kind::ForeachPoint, {dom, statement("the body of 'foreach'")});
      }
      if (accept("area")) {
        expect("in");
        Program dom = term_of(Sort::Collection, "the domain of 'foreach area'");
        return build(start, Kind::ForeachArea, {dom, statement("the body of 'foreach'")});
      }
      fail("expected 'point' or 'area' after 'foreach'" + found());
    }
    if (w == "repeat") {
      ++pos_;
      Program n = term_of(Sort::Number, "the count of 'repeat'");
      expect("times");
      return build(start, Kind::Repeat, {n, statement("the body of 'repeat'")});
    }
    if (w == "if" || w == "while") {
      ++pos_;
      Program c = term_of(Sort::Condition, "the condition");
      return build(start, w == "if" ? Kind::If : Kind::While, {c, statement("the body")});
    }
    if (w == "not") {
      ++pos_;
      Program x = term();
      if (x->sort == Sort::Condition) return build(start, Kind::CondNot, {x});
      if (x->sort == Sort::Filter) return build(start, Kind::FilterNot, {x});
      fail_at(start, std::string("'not' of ") + sort_name(x->sort));
    }
    if (w == "robot") {
      ++pos_;
      if (accept("has"))
        return build(start, Kind::RobotHas, {term_of(Sort::Item, "the object of 'robot has'")});
      expect("at");
      Program x = term();
      if (x->sort == Sort::Point) return build(start, Kind::RobotAtPoint, {x});
      if (x->sort == Sort::Area) return build(start, Kind::RobotAtArea, {x});
      fail_at(start, std::string("'robot at' of ") + sort_name(x->sort));
    }
    if (w == "is") {
      ++pos_;
      return filter_word(start, std::nullopt);
    }
    if (w == "has" && (at("color", 1) || at("colour", 1) || at("shape", 1))) {
      ++pos_;
      const bool shape = word() == "shape";
      return filter_word(start, shape ? Kind::Shape : Kind::Color);
    }
    if (w == "area" && at("with", 1)) {
      pos_ += 2;
      expect("corners");
      Program a = term_of(Sort::Point, "a corner");
      expect("and");
      Program b = term_of(Sort::Point, "a corner");
      return build(start, Kind::Corners, {a, b});
    }
    if (w == "item") {
      Program i = item();
      if (!at("at")) return chain(start, i);  // e.g. a braced item template
      ++pos_;
      Program x = term();
      if (x->sort == Sort::Point) return build(start, Kind::ItemAtPoint, {i, x});
      if (x->sort == Sort::Area) return build(start, Kind::ItemAtArea, {i, x});
      fail_at(start, std::string("'item at' of ") + sort_name(x->sort));
    }
    Program first = term();
    if (first->sort == Sort::Item && accept("at")) {  // a template `{$1 at $2}`
      Program x = term();
      if (x->sort == Sort::Point) return build(start, Kind::ItemAtPoint, {first, x});
      if (x->sort == Sort::Area) return build(start, Kind::ItemAtArea, {first, x});
      fail_at(start, std::string("'item at' of ") + sort_name(x->sort));
    }
    if (at(";")) {
      std::vector<Program> stmts{expect_sort(start, first, Sort::Action, "a sequence element")};
      while (accept(";")) {
        if (at("}")) break;  // trailing ';'
        stmts.push_back(statement("a sequence element"));
      }
      return make_seq(std::move(stmts));
    }
    return chain(start, first);
  }

  Program filter_word(std::size_t start, std::optional<Kind> kind) {
    if (is_hole_of(Sort::Color) || is_hole_of(Sort::Shape) || is_hole_of(Sort::Property))
      return build(start, Kind::FilterIs, {hole()});
    const std::size_t wpos = here();
    std::string v = word();
    if (v == "}" || v == "{" || v == ";") fail_at(wpos, "expected a colour or shape word");
    if (!kind) kind = is_shape_word(v) ? Kind::Shape : Kind::Color;
    return build(start, Kind::FilterIs, {make_word(*kind, v)});
  }

  // Left-associative binary chain `x op y op z ...` inside braces.
  Program chain(std::size_t start, Program left) {
    for (;;) {
      const std::string* t = peek();
      if (t == nullptr || *t == "}") return left;
      const std::string op = *t;
      ++pos_;
      Program right = term();
      left = build(start, binary_kind(start, op, left->sort), {left, right});
    }
  }

  Kind binary_kind(std::size_t start, const std::string& op, Sort s) {
    if (op == "+" && s == Sort::Number) return Kind::Add;
    if (op == "-" && s == Sort::Number) return Kind::Sub;
    if (op == "containing") {
      if (s == Sort::Area) return Kind::AreaContaining;
      if (s == Sort::Collection) return Kind::CollContaining;
    }
    if (op == "minus") {
      if (s == Sort::Area) return Kind::AreaMinus;
      if (s == Sort::Collection) return Kind::CollMinus;
    }
    if (op == "and" || op == "or") {
      const bool a = op == "and";
      switch (s) {
        case Sort::Condition:
          return a ? Kind::CondAnd : Kind::CondOr;
        case Sort::Area:
          return a ? Kind::AreaAnd : Kind::AreaOr;
        case Sort::Collection:
          return a ? Kind::CollAnd : Kind::CollOr;
        case Sort::Filter:
          return a ? Kind::FilterAnd : Kind::FilterOr;
        default:
          break;
      }
    }
    fail_at(start, "'" + op + "' cannot follow " + sort_name(s));
  }

  Program visit(std::size_t start) {
    expect("visit");
    Program target = term();
    std::vector<Program> kids{target};
    if (accept("while")) {
      expect("avoiding");
      kids.push_back(term_of(Sort::Area, "the avoided area"));
    }
    switch (target->sort) {
      case Sort::Point:
        return build(start, Kind::VisitPoint, std::move(kids));
      case Sort::Area:
        return build(start, Kind::VisitArea, std::move(kids));
      case Sort::Collection:
        return build(start, Kind::VisitCollection, std::move(kids));
      default:
        fail_at(start, std::string("cannot visit ") + sort_name(target->sort));
    }
  }
};

}  // namespace

std::vector<std::string> tokenize(std::string_view text) {
  std::vector<std::string> out;
  for (auto& t : lex(text)) out.push_back(std::move(t.text));
  return out;
}

std::optional<double> number_value(std::string_view t) {
  for (std::size_t i = 0; i < kNumberWords.size(); ++i)
    if (t == kNumberWords[i]) return static_cast<double>(i);
  // -?digits[.digits]
  std::size_t i = 0;
  const std::size_t n = t.size();
  if (i < n && t[i] == '-') ++i;
  const std::size_t int_start = i;
  while (i < n && is_digit(t[i])) ++i;
  if (i == int_start) return std::nullopt;
  if (i < n && t[i] == '.') {
    const std::size_t frac_start = ++i;
    while (i < n && is_digit(t[i])) ++i;
    if (i == frac_start) return std::nullopt;
  }
  if (i != n) return std::nullopt;
  double v = 0;
  auto res = std::from_chars(t.data(), t.data() + n, v);
  if (res.ec != std::errc() || res.ptr != t.data() + n) return std::nullopt;
  if (v < -99 || v > 99) return std::nullopt;
  return v + 0.0;  // -0 -> 0
}

std::string render(const Program& p) {
  std::string out;
  render_to(p, out);
  return out;
}

Program read_canonical(std::string_view text, Sort sort) {
  return Reader(text, nullptr).read(sort);
}

Program read_template(std::string_view text, Sort sort, const std::vector<Sort>& hole_sorts) {
  return Reader(text, &hole_sorts).read(sort);
}

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
