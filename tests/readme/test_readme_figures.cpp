// The figure blocks of the README and the docs pages hold exactly what their commands print today
// (docs/experiments.md §7): every block between `<!-- figures: COMMAND -->` and
// `<!-- end figures -->` in README.md or docs/*.md is re-run here and compared byte for byte. A
// change that moves a figure fails this test until `bash scripts/readme-figures` has regenerated
// the pages. The commands run in a scratch folder that looks like the repository root (build/,
// configs/, data/, examples/, docs/ linked).
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_test_support.hpp"

namespace fs = std::filesystem;

namespace {

struct Block {
  std::string command, content;
  std::string file;  ///< the page, relative to the source tree
  int line = 0;
  bool closed = false;
};

const std::string kOpen = "<!-- figures: ", kOpenEnd = " -->", kClose = "<!-- end figures -->";

std::vector<Block> figure_blocks(const std::filesystem::path& src, const std::string& page) {
  std::ifstream in(src / page);
  REQUIRE(in.good());
  std::vector<Block> out;
  bool inside = false, fence = false;
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    // A marker inside a fenced code block is an example of the syntax (docs/experiments.md §7).
    if (!inside && line.rfind("```", 0) == 0) fence = !fence;
    if (fence) continue;
    if (line.rfind(kOpen, 0) == 0 && line.size() > kOpen.size() + kOpenEnd.size() &&
        line.compare(line.size() - kOpenEnd.size(), kOpenEnd.size(), kOpenEnd) == 0) {
      INFO(page << " line " << n << ": a figures block opens inside another");
      CHECK_FALSE(inside);
      out.push_back({line.substr(kOpen.size(), line.size() - kOpen.size() - kOpenEnd.size()), "",
                     page, n, false});
      inside = true;
    } else if (line == kClose) {
      INFO(page << " line " << n << ": an end marker without a block");
      CHECK(inside);
      if (inside) out.back().closed = true;
      inside = false;
    } else if (inside) {
      out.back().content += line + "\n";
    }
  }
  return out;
}

// README.md, then the pages of docs/ in name order.
std::vector<Block> figure_blocks_of_pages(const fs::path& src) {
  std::vector<std::string> pages;
  for (const auto& e : fs::directory_iterator(src / "docs"))
    if (e.path().extension() == ".md") pages.push_back("docs/" + e.path().filename().string());
  std::sort(pages.begin(), pages.end());
  pages.insert(pages.begin(), "README.md");
  std::vector<Block> out;
  for (const auto& page : pages) {
    auto more = figure_blocks(src, page);
    out.insert(out.end(), more.begin(), more.end());
  }
  return out;
}

// Standard output only (progress and notes go to standard error, kept apart in `log`).
flipper::clitest::Run run_in(const fs::path& dir, const std::string& command, const fs::path& log) {
  return flipper::clitest::run_shell("cd '" + dir.string() + "' && HOME='" + dir.string() +
                                     "/home' sh -c '" + command + "' 2>'" + log.string() +
                                     "' < /dev/null");
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

}  // namespace

TEST_CASE("every README figure block is what its command prints now", "[readme][figures]") {
  const fs::path src = FLIPPER_SOURCE_DIR;
  const auto blocks = figure_blocks_of_pages(src);
  // The dev replay's headline and oracles, the parser x scorer table and the planner table
  // (docs/replay.md, docs/benchmarks.md), at least.
  REQUIRE(blocks.size() >= 3);
  const fs::path dir = fs::path(FLIPPER_BINARY_DIR) / "tests" / "tmp" / "readme-figures";
  fs::remove_all(dir);
  fs::create_directories(dir / "home");
  fs::create_directory_symlink(FLIPPER_BINARY_DIR, dir / "build");
  for (const char* d : {"configs", "data", "examples", "docs"})
    fs::create_directory_symlink(src / d, dir / d);
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const Block& b = blocks[i];
    INFO(b.file << " line " << b.line << ": <!-- figures: " << b.command << " -->");
    REQUIRE(b.closed);
    REQUIRE_FALSE(b.command.empty());
    REQUIRE(b.command.find('\'') == std::string::npos);
    const fs::path log = dir / ("block-" + std::to_string(i) + ".log");
    const auto r = run_in(dir, b.command, log);
    INFO("its standard error:\n" << read(log));
    REQUIRE(r.status == 0);
    REQUIRE_FALSE(r.out.empty());
    INFO(b.file << " is stale: `bash scripts/readme-figures` regenerates it");
    CHECK(r.out == b.content);
  }
}
