// Fuzz target: world JSON through a world plugin, loaded by the kernel as a session's `world`
// request does (kernel/runtime load_world_file: the plugin's load, its errors guarded).
// Built twice: fuzz_world_grid2d (FLIPPER_FUZZ_WORLD_CONFIG = the embedded default) and
// fuzz_world_octomap3d (configs/octomap-astar.yaml).
// Input: a world object. Oracles: loading either throws Error(bad_world, world_too_large,
// file_too_large or not_a_regular_file) or gives a state whose saved text loads again and saves
// to the same text (save/load round trip); and the same text with its "walls" and "rooms" spelled
// with an escape, which only the full JSON parse reads (the SDK's point scanner declines such a
// key), loads to the same state or is refused with the same code.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "flipper/kernel/config.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/wiring/config_schema.hpp"
#include "support/fuzz_support.hpp"

namespace fz = flipper::fuzz;
namespace sdk = flipper::sdk;
using flipper::kernel::Config;
using flipper::kernel::Runtime;

namespace {

std::unique_ptr<Runtime> g_runtime;

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "world (%s): %s\n  %s\n", FLIPPER_FUZZ_WORLD_PLUGIN, what, detail.c_str());
  std::abort();
}

// The documented refusals of a world (docs/protocol.md): a bad document, too many cells, an
// OctoMap file that is too large or not a regular file.
bool documented_refusal(const std::string& code) {
  return code == sdk::codes::kBadWorld || code == sdk::codes::kWorldTooLarge ||
         code == sdk::codes::kFileTooLarge || code == sdk::codes::kNotARegularFile;
}

// `"walls"` and `"rooms"` with one letter as a \u escape: inside any JSON string the same text.
std::string escaped_keys(std::string text) {
  for (const auto& [key, escaped] :
       {std::pair<std::string, std::string>{"\"walls\"", "\"wa\\u006cls\""},
        {"\"rooms\"", "\"roo\\u006ds\""}})
    for (auto at = text.find(key); at != std::string::npos;
         at = text.find(key, at + escaped.size()))
      text.replace(at, key.size(), escaped);
  return text;
}

// The saved state, or "refused: CODE".
std::string load_or_code(const std::string& text) {
  try {
    return g_runtime->world.borrow()->save(flipper::kernel::load_world_file(*g_runtime, text));
  } catch (const sdk::Error& e) {
    return "refused: " + e.code();
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (chdir(fz::source_dir().c_str()) != 0) std::abort();
  const char* config = FLIPPER_FUZZ_WORLD_CONFIG;
  std::optional<std::string> file;
  if (*config != 0) file = fz::source_dir() + "/" + config;
  g_runtime = flipper::kernel::make_runtime(
      // A smaller world limit than the default keeps each input cheap (same code paths).
      flipper::wiring::load_config(file, {"rewriter=null", "similarity=null",
                                          "lexicon.path=:memory:", "world.max_cells=1048576"}));
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(fz::as_text(data, size));
  // Only JSON text: load_world_file reads anything else as a file path.
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos || text[first] != '{') return -1;

  sdk::WorldState state;
  try {
    state = flipper::kernel::load_world_file(*g_runtime, text);
  } catch (const sdk::Error& e) {
    if (!documented_refusal(e.code()))
      fail("error code is not a documented world refusal", e.code() + ": " + e.what());
    if (const std::string other = load_or_code(escaped_keys(text)); other != "refused: " + e.code())
      fail("the full parse (keys escaped) reads it differently", e.code() + "\n  " + other);
    return 0;
  }
  const std::string saved = g_runtime->world.borrow()->save(state);
  if (const std::string other = load_or_code(escaped_keys(text)); other != saved)
    fail("the full parse (keys escaped) reads it differently", saved + "\n  " + other);
  std::string again;
  try {
    again = g_runtime->world.borrow()->save(flipper::kernel::load_world_file(*g_runtime, saved));
  } catch (const sdk::Error& e) {
    fail("saved world does not load again", saved + "\n  " + e.what());
  }
  if (again != saved) fail("save/load/save differs", saved + "\n  " + again);
  return 0;
}
