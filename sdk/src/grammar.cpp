// Grammar files (grammar.hpp): parsing rule lines, category sorts, rule meanings.
#include "flipper/sdk/grammar.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

namespace {

const std::unordered_map<std::string, Sort>& sort_table() {
  static const std::unordered_map<std::string, Sort> table = {
      {"$ROOT", Sort::Action},
      {"$Action", Sort::Action},
      {"$Actions", Sort::Action},
      {"$Situation", Sort::Condition},
      {"$Situations", Sort::Condition},
      {"$Point", Sort::Point},
      {"$Area", Sort::Area},
      {"$Areas", Sort::Area},
      {"$PointList", Sort::Area},
      {"$AreaCollection", Sort::Collection},
      {"$AreaCollections", Sort::Collection},
      {"$AreaList", Sort::Collection},
      {"$Item", Sort::Item},
      {"$CountedItem", Sort::CountedItem},
      {"$PropertySet", Sort::Filter},
      {"$PropertySets", Sort::Filter},
      {"$Number", Sort::Number},
      {"$Numbers", Sort::Number},
      {"$Direction", Sort::Direction},
      {"$Color", Sort::Color},
      {"$Shape", Sort::Shape},
      {"$ItemAct", Sort::ItemAct},
      {"$Property", Sort::Property},
  };
  return table;
}

// "$Number.token" -> "$Number"; others unchanged.
std::string base_category(const std::string& category) {
  const auto dot = category.find('.');
  return dot == std::string::npos ? category : category.substr(0, dot);
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split_ws(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

[[noreturn]] void bad(const std::string& source, int line, const std::string& what) {
  throw Error(codes::kBadGrammar, source + ":" + std::to_string(line) + ": " + what);
}

bool is_category_name(const std::string& w) {
  return w.size() > 1 && w[0] == '$';
}

std::vector<std::string> lower_all(std::vector<std::string> words) {
  for (auto& w : words)
    std::transform(w.begin(), w.end(), w.begin(), [](unsigned char c) { return std::tolower(c); });
  return words;
}

}  // namespace

Sort category_sort(const std::string& category) {
  const auto& table = sort_table();
  auto it = table.find(base_category(category));
  if (it == table.end()) throw Error(codes::kBadGrammar, "unknown category '" + category + "'");
  return it->second;
}

std::string normalize_category(const std::string& category) {
  std::string c = base_category(category);
  if (c == "$Actions") return "$Action";
  if (c == "$Areas") return "$Area";
  if (c == "$Numbers") return "$Number";
  if (c == "$Situations") return "$Situation";
  if (c == "$PropertySets") return "$PropertySet";
  if (c == "$AreaCollections") return "$AreaCollection";
  return c;
}

bool class_matches(const Grammar& g, Symbol::Type type, std::string_view token) {
  auto in = [&](const std::vector<std::string>& words) {
    return std::find(words.begin(), words.end(), token) != words.end();
  };
  switch (type) {
    case Symbol::Type::number:
      return number_value(token).has_value();
    case Symbol::Type::color:
      return in(g.colors) || (token == "grey" && std::find(g.colors.begin(), g.colors.end(),
                                                           "gray") != g.colors.end());
    case Symbol::Type::shape:
      return in(g.shapes);
    case Symbol::Type::direction:
      return in(g.directions);
    case Symbol::Type::token:
    case Symbol::Type::category:
      return false;
  }
  return false;
}

Program apply_rule(const Rule& rule, const std::vector<Program>& kids, std::string_view token) {
  if (rule.sem) return kids.empty() ? rule.sem : substitute(rule.sem, kids);
  if (rule.rhs.size() == 1) {
    switch (rule.rhs[0].type) {
      case Symbol::Type::number: {
        auto v = number_value(token);
        if (!v) throw Error(codes::kBadProgram, "'" + std::string(token) + "' is not a number");
        return make_num(*v);
      }
      case Symbol::Type::color:
        return make_word(Kind::Color, std::string(token));
      case Symbol::Type::shape:
        return make_word(Kind::Shape, std::string(token));
      case Symbol::Type::direction:
        return make_word(Kind::Direction, std::string(token));
      default:
        break;
    }
  }
  // @append: $1 is a list, $2 an element.
  if (kids.size() == 2 && kids[0] &&
      (kids[0]->kind == Kind::PointList || kids[0]->kind == Kind::AreaList)) {
    std::vector<Program> elems = kids[0]->kids;
    elems.push_back(kids[1]);
    return make(kids[0]->kind, std::move(elems));
  }
  throw Error(codes::kBadProgram, "rule " + rule.id + " has no meaning for these operands");
}

Grammar parse_grammar(const std::string& text, const std::string& source,
                      std::vector<std::string> colors, std::vector<std::string> shapes,
                      std::vector<std::string> directions) {
  Grammar g;
  g.colors = lower_all(std::move(colors));
  for (auto& c : g.colors)
    if (c == "grey") c = "gray";
  g.shapes = lower_all(std::move(shapes));
  g.directions = directions.empty() ? std::vector<std::string>{"up", "down", "left", "right"}
                                    : lower_all(std::move(directions));
  std::istringstream in(text);
  std::string raw;
  int line_no = 0;
  while (std::getline(in, raw)) {
    ++line_no;
    std::string line = raw;
    if (auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    line = trim(line);
    if (line.empty()) continue;
    const auto arrow = line.find("->");
    if (arrow == std::string::npos) bad(source, line_no, "expected 'LHS -> RHS [=> template]'");
    auto rule = std::make_shared<Rule>();
    rule->id = "core:" + std::to_string(line_no);
    rule->lhs = trim(line.substr(0, arrow));
    if (!is_category_name(rule->lhs) || rule->lhs.find(' ') != std::string::npos)
      bad(source, line_no, "the left-hand side '" + rule->lhs + "' is not a category");
    Sort lhs_sort{};
    try {
      lhs_sort = category_sort(rule->lhs);
    } catch (const Error& e) {
      bad(source, line_no, e.what());
    }
    std::string rest = line.substr(arrow + 2);
    std::string tmpl;
    bool has_tmpl = false;
    if (auto fat = rest.find("=>"); fat != std::string::npos) {
      tmpl = trim(rest.substr(fat + 2));
      rest = rest.substr(0, fat);
      has_tmpl = true;
    }
    std::vector<Sort> hole_sorts;
    std::size_t classes = 0;
    for (const auto& w : split_ws(rest)) {
      Symbol s;
      s.text = w;
      if (w == "@number")
        s.type = Symbol::Type::number;
      else if (w == "@color")
        s.type = Symbol::Type::color;
      else if (w == "@shape")
        s.type = Symbol::Type::shape;
      else if (w == "@direction")
        s.type = Symbol::Type::direction;
      else if (w[0] == '@')
        bad(source, line_no, "unknown token class '" + w + "'");
      else if (is_category_name(w)) {
        s.type = Symbol::Type::category;
        try {
          hole_sorts.push_back(category_sort(w));
        } catch (const Error& e) {
          bad(source, line_no, e.what());
        }
      } else {
        s.type = Symbol::Type::token;
        std::transform(s.text.begin(), s.text.end(), s.text.begin(),
                       [](unsigned char c) { return std::tolower(c); });
      }
      if (s.type != Symbol::Type::token && s.type != Symbol::Type::category) ++classes;
      rule->rhs.push_back(std::move(s));
    }
    if (rule->rhs.empty()) bad(source, line_no, "empty right-hand side");
    if (classes > 0) {
      if (rule->rhs.size() != 1)
        bad(source, line_no,
            "a token class (@number, @color, ...) must be the whole right-hand side");
      if (has_tmpl && tmpl != "$1")
        bad(source, line_no, "a token-class rule takes no template (its meaning is the token)");
      static const std::unordered_map<std::string, Sort> class_sort = {
          {"@number", Sort::Number},
          {"@color", Sort::Color},
          {"@shape", Sort::Shape},
          {"@direction", Sort::Direction}};
      if (class_sort.at(rule->rhs[0].text) != lhs_sort)
        bad(source, line_no, rule->rhs[0].text + " cannot yield " + rule->lhs);
    } else if (has_tmpl && tmpl == "@append") {
      const std::string base = base_category(rule->lhs);
      if ((base != "$PointList" && base != "$AreaList") || rule->rhs.size() != 3 ||
          rule->rhs[0].text != rule->lhs || rule->rhs[1].text != "," ||
          rule->rhs[2].type != Symbol::Type::category)
        bad(source, line_no, "@append needs the form '$PointList -> $PointList , $Point'");
    } else {
      if (!has_tmpl) {
        if (hole_sorts.size() != 1 || rule->rhs.size() != 1)
          bad(source, line_no, "missing '=> template'");
        tmpl = "$1";
      }
      try {
        rule->sem = read_template(tmpl, lhs_sort, hole_sorts);
      } catch (const Error& e) {
        bad(source, line_no, "bad template '" + tmpl + "': " + e.what());
      }
    }
    g.rules.push_back(std::move(rule));
  }
  if (g.rules.empty()) throw Error(codes::kBadGrammar, source + ": no rules");
  return g;
}

Grammar parse_grammar(const std::string& text, const std::string& source,
                      std::vector<std::string> colors, std::vector<std::string> shapes) {
  return parse_grammar(text, source, std::move(colors), std::move(shapes), {});
}

Grammar load_grammar_file(const std::string& path, std::vector<std::string> colors,
                          std::vector<std::string> shapes, std::vector<std::string> directions) {
  std::ifstream in(path);
  if (!in) throw Error(codes::kBadGrammar, "cannot read grammar file '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_grammar(text.str(), path, std::move(colors), std::move(shapes),
                       std::move(directions));
}

Grammar load_grammar_file(const std::string& path, std::vector<std::string> colors,
                          std::vector<std::string> shapes) {
  return load_grammar_file(path, std::move(colors), std::move(shapes), {});
}

std::string describe(const Rule& rule) {
  std::string out = rule.lhs + " ->";
  for (const auto& s : rule.rhs) out += " " + s.text;
  if (rule.sem) {
    out += " => " + render(rule.sem);
  } else if (rule.rhs.size() == 3) {
    out += " => @append";
  }
  return out;
}

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
