// Finding the plot scripts and a Python with matplotlib, and running them (plots.hpp).
#include "flipper/record/plots.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

namespace flipper::record {
namespace fs = std::filesystem;
namespace {

// The exit status the plot scripts use for "matplotlib cannot be imported" (apps/plots).
constexpr int kNoMatplotlib = 3;

std::string quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

struct Ran {
  int status = -1;
  std::string output;
};

Ran run(const std::string& command) {
  Ran r;
  FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  if (p == nullptr) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), p) != nullptr) r.output += buf.data();
  const int raw = ::pclose(p);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return r;
}

std::vector<std::string> interpreters() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("FLIPPER_PYTHON"); env != nullptr && *env != '\0') return {env};
  out.push_back("python3");
  if (fs::exists("/usr/bin/python3")) out.push_back("/usr/bin/python3");
  return out;
}

}  // namespace

std::string plots_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  const fs::path dir = exe.parent_path().parent_path() / FLIPPER_RECORD_INSTALLED_PLOTS_DIR;
  const fs::path real = fs::canonical(dir, ec);
  return ec ? std::string() : real.string();
}

PlotOutcome draw_plots(const std::string& script, const std::string& run_dir) {
  const std::string dir = plots_dir();
  const std::string how =
      " Install Python 3 with matplotlib (Debian: apt-get install python3-matplotlib; or set "
      "FLIPPER_PYTHON to a Python that has it), then draw them with `flipper replay plot " +
      run_dir + "`.";
  if (dir.empty() || !fs::is_regular_file(fs::path(dir) / script))
    return {PlotOutcome::Status::skipped,
            "plots skipped: the plot scripts are not installed (looked for <exe>/../share/"
            "flipper/plots/" +
                script + ").",
            {}};
  std::string tried;
  for (const auto& python : interpreters()) {
    const Ran r =
        run(quote(python) + " " + quote((fs::path(dir) / script).string()) + " " + quote(run_dir));
    if (r.status == 0) {
      PlotOutcome drawn{PlotOutcome::Status::drawn, r.output, {}};
      // The versions that drew them (docs/experiments.md §2): "3.11.2 3.6.3".
      const Ran v = run(quote(python) +
                        " -c 'import sys, matplotlib; "
                        "print(sys.version.split()[0], matplotlib.__version__)'");
      const auto space = v.output.find(' ');
      if (v.status == 0 && space != std::string::npos) {
        std::string mpl = v.output.substr(space + 1);
        while (!mpl.empty() && (mpl.back() == '\n' || mpl.back() == '\r')) mpl.pop_back();
        drawn.versions = {
            {"python", python}, {"python_version", v.output.substr(0, space)}, {"matplotlib", mpl}};
      }
      return drawn;
    }
    if (r.status == kNoMatplotlib || r.status == 127 || r.status == 126) {
      tried += (tried.empty() ? "" : ", ") + python;
      continue;
    }
    return {PlotOutcome::Status::failed,
            "plots failed (" + python + " " + script + ", exit " + std::to_string(r.status) +
                "):\n" + r.output,
            {}};
  }
  return {PlotOutcome::Status::skipped,
          "plots skipped: no Python with matplotlib (tried " + tried + ")." + how,
          {}};
}

}  // namespace flipper::record
