// The rows of the bad-input table (see bad_input_cases.hpp). Each message excerpt was checked
// against the answer the fixed binary gives; each row failed (crash, hang, wrong code or message)
// before the fix it guards.
#include "bad_input_cases.hpp"

#include <nlohmann/json.hpp>
#include <sstream>

namespace flipper::limitstest {
namespace {

using Json = nlohmann::json;

std::string words(const std::string& word, std::size_t n) {
  std::string out;
  out.reserve(n * (word.size() + 1));
  for (std::size_t i = 0; i < n; ++i) out += (i ? " " : "") + word;
  return out;
}

std::string query(const std::string& text) {
  return Json{{"op", "query"}, {"text", text}}.dump();
}

std::string define(const std::string& head, const std::vector<std::string>& body) {
  return Json{{"op", "define"}, {"head", head}, {"body", body}}.dump();
}

std::string world_file(const std::string& path) {
  return Json{{"op", "world"}, {"file", path}}.dump();
}

std::vector<std::string> none(const Scratch&) {
  return {};
}

}  // namespace

std::vector<std::string> session_settings() {
  return {"--set", "lexicon.path=:memory:",   "--set", "session.cpu_budget_ms=1000",
          "--set", "world.max_cells=9000000", "--set", "input.max_file_bytes=2000000",
          "--set", "input.max_tokens=2000",   "--set", "induction.generalize=false"};
}

const std::vector<SessionRow>& session_rows() {
  static const std::vector<SessionRow> rows = {
      {"invalid UTF-8 in a request line", "bad_json", "the line is not valid JSON", none,
       [](const Scratch&) { return std::string("{\"op\":\"query\",\"text\":\"\xff\"}"); }},
      {"a number beyond double range (`1e999`)", "bad_json", "number overflow parsing '1e999'",
       none,
       [](const Scratch&) {
         return std::string(R"({"op":"query","text":"move left","k":1e999})");
       }},
      {"a 400-digit integer", "bad_json", "number overflow parsing", none,
       [](const Scratch&) { return R"({"op":"state","id":)" + std::string(400, '9') + "}"; }},
      {"`id` nested 50,000 deep", "too_deep", "nested deeper than input.max_json_depth = 64 levels",
       none,
       [](const Scratch&) {
         return R"({"op":"state","id":)" + std::string(50000, '[') + "1" + std::string(50000, ']') +
                "}";
       }},
      {"a request line over `input.max_line_bytes` (2 MiB here)", "input_too_long",
       "the limit is input.max_line_bytes = 1048576", none,
       [](const Scratch&) { return query(std::string(2 << 20, 'a')); }},
      {"a request line of `input.max_line_bytes` + 1 bytes", "input_too_long",
       "the request line has 1048577 bytes; the limit is input.max_line_bytes = 1048576", none,
       [](const Scratch&) {
         const std::string head = R"({"op":"query","text":")", tail = R"("})";
         return head + std::string((1u << 20) + 1 - head.size() - tail.size(), 'a') + tail;
       }},
      {"a query of `input.max_tokens` + 1 tokens", "input_too_long",
       "the utterance has 401 tokens; the limit is input.max_tokens = 400", none,
       [](const Scratch&) { return query(words("a", 401)); }, true},
      {"a define head of `input.max_tokens` + 1 tokens", "input_too_long",
       "the head has 2001 tokens; the limit is input.max_tokens = 2000", none,
       [](const Scratch&) { return define(words("zz", 2001), {"move left"}); }},
      {"a define body line of `input.max_tokens` + 1 tokens", "input_too_long",
       "body line 1 has 2001 tokens; the limit is input.max_tokens = 2000", none,
       [](const Scratch&) { return define("glorb", {words("a", 2001)}); }},
      {"a query over `input.max_tokens` (default 400)", "input_too_long",
       "the utterance has 450 tokens; the limit is input.max_tokens = 400", none,
       [](const Scratch&) { return query(words("a", 450)); }, true},
      {"`'{'`×990 + `move left` + `'}'`×990 at the default limits", "input_too_long",
       "the utterance has 1982 tokens; the limit is input.max_tokens = 400", none,
       [](const Scratch&) {
         return query(std::string(990, '{') + "move left" + std::string(990, '}'));
       },
       true},
      {"a query over `input.max_chars`", "input_too_long",
       "the utterance has 3000 characters; the limit is input.max_chars = 2000", none,
       [](const Scratch&) { return query(std::string(3000, 'a')); }},
      {"a define head of 65,535 tokens", "input_too_long",
       "the head has 65535 tokens; the limit is input.max_tokens = 2000", none,
       [](const Scratch&) { return define(words("zz", 65535), {"move left"}); }},
      {"a define head of 110 KB", "input_too_long",
       "the head has 55000 tokens; the limit is input.max_tokens = 2000", none,
       [](const Scratch&) { return define(words("a", 55000), {"move left"}); }},
      {"a define body line of 65,535 tokens", "input_too_long",
       "body line 2 has 65535 tokens; the limit is input.max_tokens = 2000", none,
       [](const Scratch&) {
         return define("glorb", {"move left", words("up", 65535)});
       }},
      {"a define body over `input.max_body_lines`", "input_too_long",
       "the body has 101 lines; the limit is input.max_body_lines = 100", none,
       [](const Scratch&) { return define("glorb", std::vector<std::string>(101, "move left")); }},
      {"`'{'`×990 + `move left` + `'}'`×990 with `input.max_tokens` 2000", "deadline_exceeded",
       "deadline exceeded while parsing: the request used more than session.cpu_budget_ms = 1000 "
       "ms of CPU time (stopped: cpu_budget)",
       none,
       [](const Scratch&) {
         return query(std::string(990, '{') + "move left" + std::string(990, '}'));
       }},
      {"`pick item not is red and …` ×30", "deadline_exceeded", "deadline exceeded while parsing",
       none,
       [](const Scratch&) {
         std::string text = "pick item not is red";
         for (int i = 1; i < 30; ++i) text += " and not is red";
         return query(text);
       }},
      {"a define whose body line parses longer than the deadline (nothing stored)",
       "deadline_exceeded", "deadline exceeded while parsing body line 1 of the definition", none,
       [](const Scratch&) {
         std::string body = "pick item not is red";
         for (int i = 1; i < 30; ++i) body += " and not is red";
         return define("glorb", {body});
       }},
      {"`k` beyond 64 bits", "bad_request",
       "field 'k' is out of range: integers go from -9223372036854775808 to 9223372036854775807",
       none,
       [](const Scratch&) {
         return std::string(R"({"op":"query","text":"move left","k":99999999999999999999})");
       }},
      {"`rank` 1e300", "rank_out_of_range",
       "field 'rank' is out of range: integers go from -9223372036854775808 to "
       "9223372036854775807",
       [](const Scratch&) { return std::vector<std::string>{query("move left")}; },
       [](const Scratch&) { return std::string(R"({"op":"accept","rank":1e300})"); }},
      {"`ranks` beyond `int` (4294967296)", "bad_request",
       "field 'ranks' must be a list of integers from 0 to 1000000, got 4294967296", none,
       [](const Scratch&) {
         return std::string(
             R"({"op":"define","head":"glorb","body":["move left"],"ranks":[4294967296]})");
       }},
      {"`world` bounds 16382² (a 89-byte request)", "world_too_large",
       "the world has 268369924 cells; the limit is world.max_cells = 9000000", none,
       [](const Scratch&) {
         return std::string(
             R"({"op":"world","world":{"bounds":{"min":[0,0],"max":[16381,16381]},"robot":{"x":0,"y":0}}})");
       }},
      {"`/dev/zero` as a world file", "not_a_regular_file",
       "world file '/dev/zero' is not a regular file", none,
       [](const Scratch&) { return world_file("/dev/zero"); }},
      {"a FIFO as a world file", "not_a_regular_file", "is not a regular file", none,
       [](const Scratch& s) { return world_file(s.fifo); }},
      {"a world file over `input.max_file_bytes`", "file_too_large",
       "bytes; the limit is input.max_file_bytes = 2000000", none,
       [](const Scratch& s) { return world_file(s.big_world); }},
      {"`foreach point in world` on 1500²", "deadline_exceeded",
       "deadline exceeded while executing",
       [](const Scratch&) {
         return std::vector<std::string>{
             R"({"op":"world","world":{"bounds":{"min":[0,0],"max":[1499,1499]},"robot":{"x":0,"y":0}}})"};
       },
       [](const Scratch&) { return query("foreach point in world visit point"); }},
  };
  return rows;
}

const std::vector<CliRow>& cli_rows() {
  static const std::vector<CliRow> rows = {
      {"a truncated plugin `.so` on the search path (`flipper plugins`)", "plugin_load_failed",
       "truncated or damaged", 2,
       [](const Scratch& s) {
         return "{flipper} plugins --set 'plugin_paths=[" + s.truncated_dir + "]'";
       }},
      {"a truncated plugin `.so` on the search path (`flipper run`)", "plugin_load_failed",
       "truncated or damaged", 2,
       [](const Scratch& s) {
         return "{flipper} run --set 'plugin_paths=[" + s.truncated_dir + "]' 'move left'";
       }},
      {"`flipper run` of `pick item not is red and …` ×30 (`session.cpu_budget_ms` 1000)",
       "deadline_exceeded",
       "deadline exceeded while parsing: the request used more than session.cpu_budget_ms = 1000 "
       "ms of CPU time (stopped: cpu_budget)",
       1,
       [](const Scratch&) {
         std::string text = "pick item not is red";
         for (int i = 1; i < 30; ++i) text += " and not is red";
         return "{flipper} run --set lexicon.path=:memory: --set session.cpu_budget_ms=1000 '" +
                text + "'";
       }},
      {"`flipper run` of 2,500 × `é` (5,000 bytes): code points count, as in a query",
       "input_too_long", "the utterance has 2500 characters; the limit is input.max_chars = 2000",
       1,
       [](const Scratch&) {
         std::string text;
         for (int i = 0; i < 2500; ++i) text += "\xc3\xa9";
         return "{flipper} run --set lexicon.path=:memory: '" + text + "'";
       }},
      {"a duplicate key in a config file", "bad_config", "duplicate key 'k' (first at line 2)", 2,
       [](const Scratch& s) { return "{flipper} config check " + s.dup_config; }},
      {"a YAML alias bomb as the config (395 bytes, 9 levels of 9 aliases: 387 million nodes), "
       "under a 2 s CPU limit",
       "bad_config",
       "YAML nodes once its aliases are expanded (an alias counts as the nodes it repeats); the "
       "limit for a config is 100000 nodes",
       2, [](const Scratch& s) { return "ulimit -t 2; {flipper} config check " + s.alias_bomb; }},
      {"the same alias bomb in a `--set` value, under a 2 s CPU limit", "bad_config",
       "the limit for a config is 100000 nodes", 2,
       [](const Scratch&) {
         std::string value = "[&a [lol,lol,lol,lol,lol,lol,lol,lol,lol]";
         std::string prev = "a";
         for (const char* name : {"b", "c", "d", "e", "f", "g", "h", "i"}) {
           value += std::string(", &") + name + " [";
           for (int i = 0; i < 9; ++i) value += (i ? ",*" : "*") + prev;
           value += "]";
           prev = name;
         }
         return "ulimit -t 2; {flipper} config print --set 'planner.params.x=" + value + "]'";
       }},
      // CPU limits: at least 3x the cost in the slowest build that runs them, the sanitizer build,
      // taken as 4x Release (docs/testing.md). Release costs (user+sys, `/usr/bin/time`, 2 cores
      // at load ~16): 40,000 params 0.22 s (ASan ~0.9 s: 5 s is 5.6x); the same 40,000 again in
      // an overlay 0.62 s (ASan ~2.5 s: 8 s is 3.2x; it was 1.67 s before merging became
      // copy-free, and 5 s was killed under ASan); 20,000 + 20,000 other params 0.34 s (ASan
      // ~1.4 s: 5 s is 3.7x; 5.9 s before, quadratic: each inherited key was looked up anew).
      {"a config giving a plugin 40,000 params, under a 5 s CPU limit", "bad_config",
       "unknown config key 'planner.params.p0'", 2,
       [](const Scratch& s) { return "ulimit -t 5; {flipper} config check " + s.many_params; }},
      {"a config extending another, each giving a plugin the same 40,000 params, under an 8 s "
       "CPU limit",
       "bad_config", "unknown config key 'planner.params.p0'", 2,
       [](const Scratch& s) { return "ulimit -t 8; {flipper} config check " + s.many_overlay; }},
      {"a config extending another, each giving a plugin 20,000 params of other names, under a "
       "5 s CPU limit",
       "bad_config", "unknown config key 'planner.params.p0'", 2,
       [](const Scratch& s) { return "ulimit -t 5; {flipper} config check " + s.other_overlay; }},
      {"a config file of 1 MiB + 1 byte", "bad_config",
       "has 1048577 bytes; the limit for a config is 1048576 bytes (1 MiB)", 2,
       [](const Scratch& s) { return "{flipper} config check " + s.big_config; }},
      {"`/dev/zero` as the config file", "bad_config",
       "config file '/dev/zero' is not a regular file", 2,
       [](const Scratch&) { return std::string("{flipper} run --config /dev/zero 'move left'"); }},
      {"a FIFO as `grammar.file`", "not_a_regular_file", "grammar file", 2,
       [](const Scratch& s) {
         return "{flipper} run --set grammar.file=" + s.fifo + " 'move left'";
       }},
      {"`/dev/zero` as `world.file`", "not_a_regular_file",
       "world file '/dev/zero' is not a regular file", 2,
       [](const Scratch&) {
         return std::string("{flipper} run --set world.file=/dev/zero 'move left'");
       }},
      {"a FIFO as `lexicon.preload`", "not_a_regular_file", "lexicon.preload file", 1,
       [](const Scratch& s) {
         return "{flipper} session --set lexicon.path=:memory: --set lexicon.preload=" + s.fifo +
                " < /dev/null";
       }},
      {"a FIFO as a world's OctoMap (`octomap3d`)", "not_a_regular_file", "is not a regular file",
       2,
       [](const Scratch& s) {
         return "{flipper} run --config configs/octomap-ompl.yaml --world " + s.octo_world +
                " 'move left'";
       }},
      {"a replay variant named `../../x`", "bad_config",
       "variant name '../../x' must be one directory name", 2,
       [](const Scratch& s) {
         return "{flipper} replay --experiment " + s.bad_variant + " --out " + s.dir + "/out";
       }},
      {"replay output on a full device", "write_failed", "File too large", 1,
       [](const Scratch& s) {
         // The file-size limit makes every write past 1 KiB fail (EFBIG), like a full disk.
         return "trap '' XFSZ; ulimit -f 1; {flipper} replay --experiment " + s.experiment +
                " --out " + s.dir + "/full";
       }},
      {"lexicon export to a full device (`/dev/full`)", "write_failed", "cannot write '/dev/full'",
       1,
       [](const Scratch& s) {
         return "{flipper} lexicon export /dev/full --set lexicon.path=" + s.lexicon;
       }},
      {"lexicon export to standard output on a full device", "write_failed",
       "cannot write standard output", 1,
       [](const Scratch& s) {
         return "{flipper} lexicon export - --set lexicon.path=" + s.lexicon + " > /dev/full";
       }},
  };
  return rows;
}

std::string render_table() {
  std::ostringstream o;
  o << "| Bad input | Where | Code | Message (excerpt) |\n|---|---|---|---|\n";
  auto cell = [](std::string s) {
    std::string out;
    for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
    return out;
  };
  for (const auto& r : session_rows())
    o << "| " << cell(r.input) << " | session" << (r.default_limits ? " (defaults)" : "") << " | `"
      << r.code << "` | " << cell(r.message) << " |\n";
  for (const auto& r : cli_rows())
    o << "| " << cell(r.input) << " | CLI, exit " << r.status << " | `" << r.code << "` | "
      << cell(r.message) << " |\n";
  return o.str();
}

}  // namespace flipper::limitstest
