// Short plan descriptions of query candidates, and the helpers that keep them short: repeated
// warnings collapsed, unknown words named.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "flipper/repl/repl.hpp"
#include "flipper/sdk/param_check.hpp"

namespace flipper::repl {
namespace {

std::string point_text(const kernel::Json& p) {
  std::string s = "[";
  for (std::size_t i = 0; i < p.size(); ++i) s += (i ? "," : "") + std::to_string(p[i].get<int>());
  return s + "]";
}

bool is_number(const std::string& t) {
  return !t.empty() && std::all_of(t.begin(), t.end(), [](unsigned char c) {
    return std::isdigit(c) != 0 || c == '.' || c == '-';
  });
}

}  // namespace

std::vector<std::string> collapse_warnings(const kernel::Json& warnings) {
  std::vector<std::string> order;
  std::map<std::string, int> count;
  for (const auto& w : warnings) {
    const std::string text = w.is_string() ? w.get<std::string>() : w.dump();
    if (count[text]++ == 0) order.push_back(text);
  }
  for (auto& text : order)
    if (count[text] > 1) text = std::to_string(count[text]) + " \u00d7 " + text;
  return order;
}

std::vector<std::string> unknown_words(const std::vector<std::string>& tokens,
                                       const std::vector<std::string>& vocabulary) {
  std::vector<std::string> out;
  for (const auto& t : tokens) {
    if (is_number(t) || std::find(vocabulary.begin(), vocabulary.end(), t) != vocabulary.end())
      continue;
    if (!t.empty() && std::ispunct(static_cast<unsigned char>(t.front())) != 0 && t.size() == 1)
      continue;
    std::string hint = sdk::did_you_mean(t, vocabulary);
    if (hint.empty()) hint = plain_word_hint(t);
    const std::string entry = "'" + t + "'" + hint;
    if (std::find(out.begin(), out.end(), entry) == out.end()) out.push_back(entry);
  }
  return out;
}

std::string describe_candidate(const kernel::Json& c, int number) {
  std::ostringstream out;
  char prob[32];
  std::snprintf(prob, sizeof prob, "%.2f", c.value("prob", 0.0));
  out << "  [" << number << "] " << c.value("formula", std::string()) << "   (p=" << prob << ")\n";
  int steps = 0;
  std::string picks, drops, end;
  for (const auto& s : c.value("trace", kernel::Json::array())) {
    const std::string act = s.value("act", std::string());
    if (act == "move") {
      ++steps;
      end = point_text(s["to"]);
      continue;
    }
    const kernel::Json& item = s["item"];
    std::string what = item.value("color", std::string()) + " " +
                       item.value("shape", std::string()) + " at " + point_text(s["at"]);
    std::string& list = act == "pick" ? picks : drops;
    list += (list.empty() ? "" : ", ") + what;
  }
  out << "      " << steps << (steps == 1 ? " step" : " steps");
  if (!end.empty()) out << " to " << end;
  out << "; picks: " << (picks.empty() ? "none" : picks)
      << "; drops: " << (drops.empty() ? "none" : drops);
  if (!c.value("realizable", true)) out << "; NOT fully realizable";
  out << '\n';
  // Not core yet no rules: a reading that leaves words out (the floating parser).
  if (c.value("induced", false) && c.value("rules", kernel::Json::array()).empty()) {
    out << "      leaves words out (no definition used)\n";
  } else if (c.value("induced", false)) {
    out << "      uses definitions:";
    for (const auto& r : c.value("rules", kernel::Json::array()))
      out << ' ' << r.get<std::string>();
    out << " (by";
    for (const auto& a : c.value("authors", kernel::Json::array()))
      out << ' ' << a.get<std::string>();
    out << ")\n";
  }
  for (const auto& w : collapse_warnings(c.value("warnings", kernel::Json::array())))
    out << "      warning: " << w << '\n';
  if (c.contains("error"))
    out << "      ERROR (" << c["error"].value("code", std::string())
        << "): " << c["error"].value("message", std::string()) << " -- cannot be chosen\n";
  return out.str();
}

}  // namespace flipper::repl
