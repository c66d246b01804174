// The lexicon a run starts from, for its manifest (docs/experiments.md §2, docs/naturalization.md
// §5 "History and governance"): the store's checksum of live rules, its last history entry and
// the tag naming that entry, if any.
#include <filesystem>

#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/record/manifest.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::record {

nlohmann::json lexicon_json(const kernel::Config& config) {
  namespace keys = naturalization::keys;
  if (!config.has(keys::kLexiconPath)) return nullptr;
  const std::string text = config.text(keys::kLexiconPath);
  if (text.empty() || text == ":memory:") return nullptr;
  const std::string path = config.resolve_path_of(keys::kLexiconPath, text);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return nullptr;  // the run starts empty
  try {
    naturalization::LexiconStoreOptions options;
    options.check_on_open = false;  // provenance, not a check of every page
    const naturalization::LexiconStore store(path, options);
    nlohmann::json out{{"path", path},
                       {"checksum", naturalization::lexicon_checksum(store.rules())}};
    if (store.has_history()) {
      const std::int64_t head = store.history_head();
      out["entry"] = head;
      out["tag"] = nullptr;
      for (const auto& t : store.tags())
        if (t.seq == head) out["tag"] = t.name;  // the newest name of this very state
    }
    return out;
  } catch (const sdk::Error& e) {
    return {{"path", path}, {"error", std::string(e.code()) + ": " + e.what()}};
  }
}

}  // namespace flipper::record
