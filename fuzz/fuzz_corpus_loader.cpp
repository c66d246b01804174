// Fuzz target: the user-study corpus loader (apps/replay load_corpus) and what the replay
// reads from it (runs, preloaded definitions, protocol worlds).
// Input: worlds.jsonl, then queries.jsonl, definitions.jsonl and original-answers.jsonl, the
// files separated by lines `%%`. Oracle: load_corpus either throws Error(bad_corpus) or gives a
// corpus whose runs, preloaded definitions and worlds can all be read.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "flipper/replay/corpus.hpp"
#include "flipper/sdk/errors.hpp"
#include "support/fuzz_support.hpp"

namespace fz = flipper::fuzz;
namespace replay = flipper::replay;
namespace sdk = flipper::sdk;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const char* const kFiles[] = {"worlds.jsonl", "queries.jsonl", "definitions.jsonl",
                                       "original-answers.jsonl"};
  const auto parts = fz::split_sections(fz::as_text(data, size), "%%", 4);
  const std::string dir = fz::scratch_dir();
  for (std::size_t i = 0; i < 4; ++i) {
    const std::string path = dir + "/" + kFiles[i];
    if (i < parts.size()) {
      fz::write_file(path, parts[i]);
    } else {
      std::remove(path.c_str());  // the optional files may be missing
    }
  }
  replay::Corpus corpus;
  try {
    corpus = replay::load_corpus(dir);
  } catch (const sdk::Error& e) {
    if (std::string(e.code()) != replay::kBadCorpus) {
      std::fprintf(stderr, "corpus_loader: error code %s: %s\n", e.code().c_str(), e.what());
      std::abort();
    }
    return 0;
  }
  for (const replay::Run& run : corpus.runs) {
    if (corpus.find_run(run.source) != &run) std::abort();
    for (const replay::Definition* d : corpus.preloaded(run.source)) (void)d->author();
    for (std::size_t i : run.commands)
      if (i >= corpus.commands.size()) std::abort();
  }
  for (const auto& [id, world] : corpus.worlds) (void)world.dump();
  return 0;
}
