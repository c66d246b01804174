// Kill-test driver: commits definitions (with two rules each) to the store named on the command
// line, starting at index argv[2], and prints "ack <index>" only after each commit returned —
// exactly when a session would send its answer.
#include <cstdio>
#include <string>

#include "flipper/naturalization/lexicon_store.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: lexicon_kill_driver STORE START\n");
    return 2;
  }
  flipper::naturalization::LexiconStore store(argv[1]);
  std::int64_t created = store.max_created();
  for (long i = std::stol(argv[2]);; ++i) {
    const std::string head = "head " + std::to_string(i);
    std::vector<flipper::naturalization::StoredRule> rules(2);
    for (auto& r : rules) {
      r.created = ++created;
      r.id = "r" + std::to_string(r.created);
      r.lhs = "$Action";
      r.rhs = {"head", "$Number"};
      r.semantics = "{repeat $1 times {pick item }}";
      r.author = "killer";
      r.head = head;
      r.body = {"repeat 3 times pick item"};
      r.how = "best";
    }
    store.add_definition({0, head, {"repeat 3 times pick item"}, "killer", i}, rules);
    std::printf("ack %ld\n", i);
    std::fflush(stdout);
  }
}
