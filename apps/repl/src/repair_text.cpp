// A repair (flipper/naturalization/repair.hpp, docs/protocol.md "Repairs") as the repl and `flipper
// run` say it: what was understood, which words were not, the nearest sentences, how to teach it.
#include "flipper/naturalization/repair.hpp"
#include "flipper/naturalization/unrealizable.hpp"
#include "flipper/repl/repl.hpp"
#include "flipper/sdk/canonical.hpp"

namespace flipper::repl {
namespace {

std::string quoted_list(const std::vector<std::string>& items) {
  std::string s;
  for (std::size_t i = 0; i < items.size(); ++i) s += (i ? ", " : "") + items[i];
  return s;
}

std::vector<std::string> word_notes(const naturalization::Repair& r) {
  std::vector<std::string> notes;
  for (const auto& w : r.words)
    notes.push_back("'" + w.word + "' (" + (w.known ? "misplaced" : "unknown") +
                    (w.did_you_mean.empty() ? "" : ", did you mean '" + w.did_you_mean + "'?") +
                    ")");
  return notes;
}

}  // namespace

std::string repair_lines(const naturalization::Repair& r, const std::string& teach) {
  std::string out;
  if (!r.understood.empty()) {
    std::vector<std::string> parts;
    for (const auto& p : r.understood)
      parts.push_back("\"" + p.text + "\" = " + sdk::render(p.program));
    out += "Understood: " + quoted_list(parts) + ".\n";
  }
  if (!r.words.empty()) out += "Not understood: " + quoted_list(word_notes(r)) + ".\n";
  if (!r.nearest.empty()) {
    out += "Nearest sentences I understand:\n";
    for (std::size_t i = 0; i < r.nearest.size(); ++i)
      out += "  " + std::to_string(i + 1) + ". " + r.nearest[i].text + "   (" + r.nearest[i].edit +
             ")\n";
  }
  if (!r.teach_body.empty()) {
    out += teach;
    for (const auto& line : r.teach_body) out += " \"" + line + "\"";
    out += ".\n";
  }
  return out;
}

std::string repair_summary(const naturalization::Repair& r) {
  std::vector<std::string> parts;
  if (!r.nearest.empty()) {
    std::vector<std::string> near;
    for (const auto& s : r.nearest) near.push_back("'" + s.text + "' (" + s.edit + ")");
    parts.push_back("nearest understood: " + quoted_list(near));
  }
  if (!r.understood.empty()) {
    std::vector<std::string> phrases;
    for (const auto& p : r.understood) phrases.push_back("'" + p.text + "'");
    parts.push_back("understood: " + quoted_list(phrases));
  }
  if (!r.words.empty()) parts.push_back("not understood: " + quoted_list(word_notes(r)));
  std::string s;
  for (const auto& p : parts) s += "; " + p;
  return s;
}

std::string unrealizable_line(const naturalization::Unrealizable& u, int dims) {
  std::string s = "Cannot be done here: " + sdk::render(u.step) + " fails at " +
                  sdk::to_string(u.at, dims) + ": " + u.why + ".";
  if (u.variant)
    return s + " Nearest that works: " + sdk::render(u.variant->program) + " (" + u.variant->edit +
           ").";
  return s + " No variant found (" + std::to_string(u.tried) + " tried).";
}

}  // namespace flipper::repl
