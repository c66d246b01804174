// Line input: GNU readline for terminals (editing, history kept across runs), std::getline
// otherwise.
#include <readline/history.h>
#include <readline/readline.h>

#include <cstdlib>
#include <filesystem>
#include <istream>
#include <memory>

#include "flipper/repl/repl.hpp"

namespace flipper::kernel::repl {
namespace {

class ReadlineReader : public LineReader {
 public:
  explicit ReadlineReader(std::string history_file) : history_file_(std::move(history_file)) {
    if (!history_file_.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(std::filesystem::path(history_file_).parent_path(), ec);
      read_history(history_file_.c_str());
    }
  }

  bool read(const char* prompt, std::string& line) override {
    char* raw = readline(prompt);
    if (raw == nullptr) return false;
    line.assign(raw);
    std::free(raw);
    if (!line.empty()) {
      add_history(line.c_str());
      if (!history_file_.empty()) {
        // Appended per line, so a crash or a second window loses nothing typed.
        if (append_history(1, history_file_.c_str()) != 0) write_history(history_file_.c_str());
        history_truncate_file(history_file_.c_str(), 1000);
      }
    }
    return true;
  }

 private:
  std::string history_file_;
};

class StreamReader : public LineReader {
 public:
  explicit StreamReader(std::istream& in) : in_(in) {}
  bool read(const char*, std::string& line) override {
    if (!std::getline(in_, line)) return false;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  }

 private:
  std::istream& in_;
};

}  // namespace

std::string default_history_file() {
  if (const char* f = std::getenv("FLIPPER_HISTORY")) return f;
  const char* home = std::getenv("HOME");
  if (home == nullptr || *home == '\0') return {};
  return std::string(home) + "/.local/share/flipper/repl_history";
}

std::unique_ptr<LineReader> make_line_reader(std::istream& in, bool terminal,
                                             const std::string& history_file) {
  if (terminal) return std::make_unique<ReadlineReader>(history_file);
  return std::make_unique<StreamReader>(in);
}

}  // namespace flipper::kernel::repl
