// Line input: GNU readline for terminals (editing, history), std::getline otherwise.
#include <readline/history.h>
#include <readline/readline.h>

#include <cstdlib>
#include <istream>
#include <memory>

#include "flipper/kernel/repl.hpp"

namespace flipper::kernel::repl {
namespace {

class ReadlineReader : public LineReader {
 public:
  bool read(const char* prompt, std::string& line) override {
    char* raw = readline(prompt);
    if (raw == nullptr) return false;
    line.assign(raw);
    std::free(raw);
    if (!line.empty()) add_history(line.c_str());
    return true;
  }
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

std::unique_ptr<LineReader> make_line_reader(std::istream& in, bool terminal) {
  if (terminal) return std::make_unique<ReadlineReader>();
  return std::make_unique<StreamReader>(in);
}

}  // namespace flipper::kernel::repl
