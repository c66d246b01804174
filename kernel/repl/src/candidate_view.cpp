// Short plan descriptions of query candidates.
#include <cstdio>
#include <sstream>

#include "flipper/kernel/repl.hpp"

namespace flipper::kernel::repl {
namespace {

std::string point_text(const Json& p) {
  std::string s = "[";
  for (std::size_t i = 0; i < p.size(); ++i) s += (i ? "," : "") + std::to_string(p[i].get<int>());
  return s + "]";
}

}  // namespace

std::string describe_candidate(const Json& c, int number) {
  std::ostringstream out;
  char prob[32];
  std::snprintf(prob, sizeof prob, "%.2f", c.value("prob", 0.0));
  out << "  [" << number << "] " << c.value("formula", std::string()) << "   (p=" << prob << ")\n";
  int steps = 0;
  std::string picks, drops;
  for (const auto& s : c.value("trace", Json::array())) {
    const std::string act = s.value("act", std::string());
    if (act == "move") {
      ++steps;
      continue;
    }
    const Json& item = s["item"];
    std::string what = item.value("color", std::string()) + " " +
                       item.value("shape", std::string()) + " at " + point_text(s["at"]);
    std::string& list = act == "pick" ? picks : drops;
    list += (list.empty() ? "" : ", ") + what;
  }
  out << "      " << steps << (steps == 1 ? " step" : " steps")
      << "; picks: " << (picks.empty() ? "none" : picks)
      << "; drops: " << (drops.empty() ? "none" : drops);
  if (!c.value("realizable", true)) out << "; NOT fully realizable";
  out << '\n';
  // Not core yet no rules: a reading that leaves words out (the floating parser).
  if (c.value("induced", false) && c.value("rules", Json::array()).empty()) {
    out << "      leaves words out (no definition used)\n";
  } else if (c.value("induced", false)) {
    out << "      uses definitions:";
    for (const auto& r : c.value("rules", Json::array())) out << ' ' << r.get<std::string>();
    out << " (by";
    for (const auto& a : c.value("authors", Json::array())) out << ' ' << a.get<std::string>();
    out << ")\n";
  }
  for (const auto& w : c.value("warnings", Json::array()))
    out << "      warning: " << w.get<std::string>() << '\n';
  if (c.contains("error"))
    out << "      ERROR (" << c["error"].value("code", std::string())
        << "): " << c["error"].value("message", std::string()) << " -- cannot be chosen\n";
  return out.str();
}

}  // namespace flipper::kernel::repl
