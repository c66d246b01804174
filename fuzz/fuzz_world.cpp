// Fuzz target: world JSON through a world plugin, loaded by the kernel as a session's `world`
// request does (kernel/runtime load_world_file: the plugin's load, its errors guarded).
// Built twice: fuzz_world_grid2d (FLIPPER_FUZZ_WORLD_CONFIG = the embedded default) and
// fuzz_world_octomap3d (configs/octomap-astar.yaml).
// Input: a world object. Oracle: loading either throws Error(bad_world) or gives a state whose
// saved text loads again and saves to the same text (save/load round trip).
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "flipper/kernel/config.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/world_format.hpp"
#include "support/fuzz_support.hpp"
#include "support/known_findings.hpp"

namespace fz = flipper::fuzz;
namespace known = flipper::fuzz::known;
namespace sdk = flipper::sdk;
namespace wf = flipper::sdk::world_format;
using flipper::kernel::Config;
using flipper::kernel::Runtime;

namespace {

std::unique_ptr<Runtime> g_runtime;

[[noreturn]] void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "world (%s): %s\n  %s\n", FLIPPER_FUZZ_WORLD_PLUGIN, what, detail.c_str());
  std::abort();
}

// Known classes: a box of millions of cells, and octomap files that are not regular files.
bool known_class(std::string_view text, int dims) {
  // parse_world lets nlohmann's out_of_range ("number overflow") escape for 1e999-like numbers,
  // which the kernel reports as plugin_error, not bad_world.
  if (known::has_huge_number(text)) return known::skip(known::Class::HugeNumber);
  wf::WorldDocument doc;
  try {
    doc = wf::parse_world(text, dims);
  } catch (const sdk::Error&) {
    return false;  // the plugin will refuse it too
  }
  const wf::Bounds b = wf::effective_bounds(doc);
  double cells = 1;
  cells *= static_cast<double>(b.max.x) - b.min.x + 1;
  cells *= static_cast<double>(b.max.y) - b.min.y + 1;
  if (dims == 3) cells *= static_cast<double>(b.max.z) - b.min.z + 1;
  if (cells > 4e6) return known::skip(known::Class::HugeWorld);
  if (doc.octomap) {
    std::error_code ec;
    if (known::names_special_path(*doc.octomap) ||
        (std::filesystem::exists(*doc.octomap, ec) &&
         !std::filesystem::is_regular_file(*doc.octomap, ec)))
      return known::skip(known::Class::NonRegular);
  }
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (chdir(fz::source_dir().c_str()) != 0) std::abort();
  const char* config = FLIPPER_FUZZ_WORLD_CONFIG;
  std::optional<std::string> file;
  if (*config != 0) file = fz::source_dir() + "/" + config;
  g_runtime = flipper::kernel::make_runtime(
      Config::load(file, {"rewriter=null", "similarity=null", "lexicon.path=:memory:"}));
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(fz::as_text(data, size));
  // Only JSON text: load_world_file reads anything else as a file path.
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos || text[first] != '{') return -1;
  const int dims = g_runtime->world.borrow()->dims();
  if (known_class(text, dims)) return -1;

  sdk::WorldState state;
  try {
    state = flipper::kernel::load_world_file(*g_runtime, text);
  } catch (const sdk::Error& e) {
    if (e.code() != sdk::codes::kBadWorld)
      fail("error code is not bad_world", e.code() + ": " + e.what());
    return 0;
  }
  const std::string saved = g_runtime->world.borrow()->save(state);
  std::string again;
  try {
    again = g_runtime->world.borrow()->save(flipper::kernel::load_world_file(*g_runtime, saved));
  } catch (const sdk::Error& e) {
    fail("saved world does not load again", saved + "\n  " + e.what());
  }
  if (again != saved) fail("save/load/save differs", saved + "\n  " + again);
  return 0;
}
