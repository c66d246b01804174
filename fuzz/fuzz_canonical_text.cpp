// Fuzz target: the canonical-text reader (sdk/canonical.hpp, docs/core-language.md §7).
// Input: one byte choosing the sort, then the text. Oracle: read_canonical either throws
// Error(bad_program) or returns a program whose rendering reads back to an equal program and
// renders to the same text again (render is a fixed point after one round).
#include <cstdio>
#include <cstdlib>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "support/fuzz_support.hpp"

namespace sdk = flipper::sdk;

namespace {

[[noreturn]] void fail(const char* what, const std::string& a, const std::string& b) {
  std::fprintf(stderr, "canonical_text: %s\n  first:  %s\n  second: %s\n", what, a.c_str(),
               b.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  constexpr int kSorts = static_cast<int>(sdk::Sort::Property) + 1;
  const auto sort = static_cast<sdk::Sort>(data[0] % kSorts);
  const std::string_view text = flipper::fuzz::as_text(data + 1, size - 1);

  for (const std::string& token : sdk::tokenize(text)) (void)sdk::number_value(token);

  sdk::Program program;
  try {
    program = sdk::read_canonical(text, sort);
  } catch (const sdk::Error& e) {
    if (e.code() != sdk::codes::kBadProgram) fail("unexpected error code", e.code(), e.what());
    return 0;
  }
  if (!program) fail("read_canonical returned null", std::string(text), "");
  const std::string rendered = sdk::render(program);
  sdk::Program again;
  try {
    again = sdk::read_canonical(rendered, sort);
  } catch (const sdk::Error& e) {
    fail("rendered text does not read back", rendered, e.what());
  }
  if (!sdk::equal(program, again)) fail("read(render(p)) != p", rendered, sdk::render(again));
  if (sdk::render(again) != rendered) fail("render not stable", rendered, sdk::render(again));
  return 0;
}
