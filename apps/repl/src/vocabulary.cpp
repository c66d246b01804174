// The words a session's parser knows, and the note for words it does not: used by `flipper repl`
// and `flipper run`, so both give the same "did you mean" (docs/language.md "How to try things").
#include <map>

#include "flipper/naturalization/naturalize_ops.hpp"
#include "flipper/naturalization/repair_extension.hpp"
#include "flipper/repl/repl.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/param_check.hpp"

namespace flipper::repl {
namespace {

// Plain words people try first that the core language does not have, and what it says
// instead (docs/language.md, "Every construct"). Only offered when no known word is close.
const std::map<std::string, std::string>& plain_words() {
  static const std::map<std::string, std::string> kWords = {
      {"go", "visit PLACE or move DIRECTION"},
      {"goto", "visit PLACE"},
      {"walk", "visit PLACE or move DIRECTION"},
      {"head", "visit PLACE"},
      {"travel", "visit PLACE"},
      {"step", "move DIRECTION"},
      {"take", "pick item"},
      {"grab", "pick item"},
      {"get", "pick item"},
      {"collect", "pick every item"},
      {"fetch", "pick item"},
      {"put", "drop item"},
      {"place", "drop item"},
      {"release", "drop item"},
      {"deliver", "drop item"},
      {"all", "every item"},
      {"everything", "every item"},
      {"twice", "repeat 2 times"},
  };
  return kWords;
}

}  // namespace

std::string plain_word_hint(const std::string& word) {
  const auto it = plain_words().find(word);
  return it == plain_words().end() ? "" : " (the core language says '" + it->second + "')";
}

std::string unknown_words_note(kernel::Session& session, const std::string& text) {
  const auto unknown = unknown_words(sdk::tokenize(text), naturalization::vocabulary(session));
  if (unknown.empty()) return {};
  std::string note = unknown.size() == 1 ? "Unknown word: " : "Unknown words: ";
  for (std::size_t i = 0; i < unknown.size(); ++i) note += (i ? ", " : "") + unknown[i];
  return note + ".";
}

}  // namespace flipper::repl
