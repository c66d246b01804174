// flipper plugin new KIND NAME [DIR]: scaffolds an out-of-tree plugin of any kind in DIR (default
// ./NAME): its CMakeLists.txt (find_package(FlipperSDK), flipper_add_plugin with its VERSION, the
// one source of the descriptor's and the sidecar's version, flipper_add_conformance_test), a
// working source with its parameters as typed handles (flipper/sdk/config_handles.hpp), a test of
// its own beside the conformance kits, and a README with the commands to build, test and load it.
// The files are the examples of examples/out-of-tree-planner and examples/plugin-templates/<kind>,
// embedded at build time (embed_templates.cmake) with their name replaced: a scaffold is exactly
// what CI builds, tests and loads (tests/kernel/out_of_tree.sh).
#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/sdk/errors.hpp"
#include "plugin_templates.hpp"

namespace flipper::cli {
namespace {

namespace fs = std::filesystem;

const std::array<std::string, 6> kKinds = {"world",  "planner",  "parser",
                                           "scorer", "rewriter", "similarity"};

// A C++ namespace, a file name, a CMake target suffix and a plugin id at once.
bool valid_name(const std::string& name) {
  static const std::array<const char*, 97> kKeywords = {
      "alignas",       "alignof",     "and",
      "and_eq",        "asm",         "auto",
      "bitand",        "bitor",       "bool",
      "break",         "case",        "catch",
      "char",          "char8_t",     "char16_t",
      "char32_t",      "class",       "compl",
      "concept",       "const",       "consteval",
      "constexpr",     "constinit",   "const_cast",
      "continue",      "co_await",    "co_return",
      "co_yield",      "decltype",    "default",
      "delete",        "do",          "double",
      "dynamic_cast",  "else",        "enum",
      "explicit",      "export",      "extern",
      "false",         "float",       "for",
      "friend",        "goto",        "if",
      "inline",        "int",         "long",
      "mutable",       "namespace",   "new",
      "noexcept",      "not",         "not_eq",
      "nullptr",       "operator",    "or",
      "or_eq",         "private",     "protected",
      "public",        "register",    "reinterpret_cast",
      "requires",      "return",      "short",
      "signed",        "sizeof",      "static",
      "static_assert", "static_cast", "struct",
      "switch",        "template",    "this",
      "thread_local",  "throw",       "true",
      "try",           "typedef",     "typeid",
      "typename",      "union",       "unsigned",
      "using",         "virtual",     "void",
      "volatile",      "wchar_t",     "while",
      "xor",           "xor_eq",      "std",
      "flipper",       "sdk",         "toolkit",
      "testing"};
  if (name.empty() || name.size() > 64 || name[0] < 'a' || name[0] > 'z') return false;
  for (char c : name)
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return false;
  return std::find(kKeywords.begin(), kKeywords.end(), name) == kKeywords.end();
}

// my_planner -> MyPlanner: the plugin's class.
std::string class_name(const std::string& name) {
  std::string out;
  bool upper = true;
  for (char c : name) {
    if (c == '_') {
      upper = true;
      continue;
    }
    out += upper && c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c;
    upper = false;
  }
  return out;
}

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos;
       at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

// The prefix of an installed Flipper SDK next to this binary (<exe>/..), if there is one.
std::string sdk_prefix() {
  std::error_code ec;
  const fs::path prefix = fs::read_symlink("/proc/self/exe", ec).parent_path().parent_path();
  if (!ec && fs::exists(prefix / "lib/cmake/FlipperSDK/FlipperSDKConfig.cmake", ec))
    return prefix.string();
  return "<the prefix of an installed Flipper SDK: cmake --install <build> --prefix P>";
}

std::string readme(const std::string& kind, const std::string& name) {
  return "# " + name + ": a Flipper " + kind + " plugin\n\n" + "Made by `flipper plugin new " +
         kind + " " + name +
         "`. Build it against an installed Flipper SDK, run its\n"
         "tests (the loader kit, the " +
         kind + " kit and your own, test_" + name +
         ".cpp) and load it:\n\n"
         "    cmake -S . -B build -DCMAKE_PREFIX_PATH=" +
         sdk_prefix() +
         "\n"
         "    cmake --build build\n"
         "    ctest --test-dir build\n"
         "    flipper plugins --set plugin_paths=[$PWD/build/plugins] --set " +
         kind + ".plugin=" + name +
         "\n\n"
         "- `" +
         name + ".cpp` is a working " + kind +
         " plugin to change. Its parameters are typed handles\n"
         "  (`flipper/sdk/config_handles.hpp`): name, default, range and description written "
         "once.\n"
         "- `VERSION` in `CMakeLists.txt` is the plugin's one version: `flipper_add_plugin` puts "
         "it in the\n"
         "  descriptor and in the sidecar `build/plugins/" +
         name +
         ".flipper.yaml`, which the kernel indexes.\n"
         "- `flipper_add_conformance_test` runs the conformance kits on the built plugin "
         "(`PARAMS name=value`\n"
         "  for parameters without a default); `test_" +
         name +
         ".cpp` creates the plugin with\n"
         "  `flipper::testing::load_plugin`, as the kernel would.\n"
         "- Threads: the kernel calls an instance for one request at a time, but runs instances "
         "concurrently\n"
         "  (`flipper/sdk/plugin.hpp`): keep per-call scratch in the instance without a lock; "
         "guard state\n"
         "  shared between instances. The kit runs two instances at once to check it.\n"
         "- CMake refuses, at configure time, a C++ standard library ABI other than the SDK's "
         "(g++ and\n"
         "  clang++ against the same libstdc++ both fit): the kernel would refuse the plugin.\n";
}

int scaffold(const std::string& kind, const std::string& name, std::string dir) {
  if (!valid_name(name))
    return report_error("plugin new", "bad_request",
                        "'" + name +
                            "' is not a plugin name: lower-case letters, digits and '_', starting "
                            "with a letter, at most 64, not a C++ keyword",
                        kExitUsage);
  if (dir.empty()) dir = name;
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_empty(dir, ec))
    return report_error("plugin new", "bad_request",
                        "'" + dir + "' exists and is not empty; choose another DIR", kExitUsage);
  fs::create_directories(dir, ec);
  if (ec)
    return report_error("plugin new", "io_error", "cannot create '" + dir + "': " + ec.message(),
                        kExitFailed);
  std::vector<std::pair<std::string, std::string>> files;  // path in dir, text
  for (const auto& t : plugin_templates()) {
    if (t.kind != kind && t.kind != "any") continue;
    std::string path(t.path), text(t.text);
    const std::string token(t.token);
    if (t.kind == "any") text = replace_all(text, "planner", kind);  // the CMakeLists.txt
    for (const auto& [from, to] :
         {std::pair{token, name}, std::pair{class_name(token), class_name(name)}}) {
      text = replace_all(text, from, to);
      path = replace_all(path, from, to);
    }
    files.emplace_back(std::move(path), std::move(text));
  }
  files.emplace_back("README.md", readme(kind, name));
  for (const auto& [path, text] : files) {
    const fs::path out = fs::path(dir) / path;
    std::ofstream f(out);
    if (!(f << text) || !f.flush())
      return report_error("plugin new", "io_error", "cannot write '" + out.string() + "'",
                          kExitFailed);
  }
  std::cout << "created the " << kind << " plugin '" << name << "' in " << dir << ":\n";
  for (const auto& f : files) std::cout << "  " << (fs::path(dir) / f.first).string() << "\n";
  std::cout << "next (" << (fs::path(dir) / "README.md").string() << "):\n"
            << "  cmake -S " << dir << " -B " << dir
            << "/build -DCMAKE_PREFIX_PATH=" << sdk_prefix() << "\n  cmake --build " << dir
            << "/build && ctest --test-dir " << dir << "/build\n";
  return kExitOk;
}

}  // namespace

void add_plugin_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("plugin", "Work on plugins of your own (flipper plugin new ...)");
  cmd->require_subcommand(1);
  auto* create = cmd->add_subcommand(
      "new", "Scaffold an out-of-tree plugin: CMakeLists, source, tests, README");
  static CommonOptions opts;
  static std::string kind, name, dir;
  add_common_options(*create, opts);
  create->add_option("kind", kind, "world, planner, parser, scorer, rewriter or similarity")
      ->required()
      ->check(CLI::IsMember(std::vector<std::string>(kKinds.begin(), kKinds.end())));
  create->add_option("name", name, "the plugin's name (a C++ identifier: my_planner)")->required();
  create->add_option("dir", dir, "where to write it (default: ./NAME); must be new or empty");
  on_run(*create, [] {
    try {
      (void)load_config(opts);  // --config and --set are checked as everywhere
      return scaffold(kind, name, dir);
    } catch (const sdk::Error& e) {
      return report_error("plugin new", e.code(), e.what(), status_for(e.code()));
    }
  });
}

}  // namespace flipper::cli
