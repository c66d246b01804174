// The kernel's config schema: every kernel key declared once, with the SDK's ParamSchema (the
// engine that checks plugins' params), in the order the effective config lists them.
#include "flipper/kernel/keys.hpp"
#include "flipper/kernel/config.hpp"

namespace flipper::kernel {
namespace {

using sdk::ParamSchema;
using sdk::ParamSpec;
using sdk::ParamType;

void add(ParamSchema& s, const keys::Int& k) {
  s.add_int(std::string(k.path), k.def, std::string(k.doc), static_cast<double>(k.min),
            static_cast<double>(k.max));
}
void add(ParamSchema& s, const keys::Bool& k) {
  s.add_bool(std::string(k.path), k.def, std::string(k.doc));
}

// A plugin section: `plugin` names the plugin (required; `def` empty: the section is optional),
// `params` is validated against the plugin's own schema (Config::plugin_params).
void add_plugin_section(ParamSchema& s, const std::string& section, const std::string& def,
                        const std::string& doc) {
  s.add_section(section, doc, def.empty());
  ParamSpec plugin{section + ".plugin",
                   ParamType::String,
                   {},
                   def.empty(),
                   "the " + section + " plugin",
                   {},
                   {},
                   {}};
  if (!def.empty()) plugin.default_value = def;
  s.add(std::move(plugin));
  s.add_map(section + ".params", "the plugin's params (`flipper plugins NAME` lists them)");
}

ParamSchema build() {
  ParamSchema s;
  add_plugin_section(s, "world", "grid2d", "the world plugin");
  s.add_path("world.file", std::string("worlds/study2018.json"), "the default world");
  s.add_double("world.resolution", 1.0, "metres per cell (plans over DDS)", 0.001, 1000);
  s.add_double_list("world.origin", {0, 0, 0}, "metres of cell (0, 0, 0) (plans over DDS)");
  add(s, keys::kMaxWorldCells);
  add_plugin_section(s, "planner", "astar", "the planner plugin");
  add_plugin_section(s, "parser", "chart", "the parser plugin");
  add_plugin_section(s, "scorer", "loglinear", "the scorer plugin");
  add_plugin_section(s, "rewriter", "", "optional: generalization by rewriting");
  add_plugin_section(s, "similarity", "", "optional: word similarity for alignment");

  s.add_section("grammar", "the core grammar and its vocabulary");
  s.add_path("grammar.file", std::string("grammars/core.grammar"), "the core grammar");
  s.add_string_list("grammar.colors",
                    {"black", "blue", "gray", "green", "orange", "pink", "purple", "red", "yellow"},
                    "colour words");
  s.add_string_list("grammar.shapes", {"triangle", "circle", "square"}, "shape words");
  s.add_string_list("grammar.directions", {},
                    "a subset of the world plugin's direction words (empty: all of them)");

  s.add_section("lexicon", "the store of induced rules (naturalization)");
  s.add_path("lexicon.path", std::string("~/.local/share/flipper/lexicon.sqlite"),
             "SQLite file (`:memory:`: none)");
  s.add_string("lexicon.sharing", "shared", "whose rules serve a user",
               {"shared", "private", "core"});
  s.add_path("lexicon.preload", std::string(), "definitions replayed at start (empty: none)");
  s.add_string("lexicon.weights", "global", "scorer weights", {"global", "per_user"});
  add(s, keys::kBusyTimeoutMs);
  add(s, keys::kSnapshotMinRules);
  s.add_string("lexicon.durability", "full",
               "full: each accept/define is on disk when answered; normal: survives any process "
               "crash, a power loss may drop the last commits (docs/naturalization.md §5)",
               {"full", "normal"});
  s.add_string("lexicon.replication", "none", "share rules between sites", {"none", "dds"});
  s.add_string("lexicon.site", "", "this site's name (replication; recorded in the history)");
  s.add_string("lexicon.conflicts", "warn",
               "a definition that changes other users' readings: shown (warn) or refused "
               "(refuse, definition_conflicts)",
               {"warn", "refuse"});

  s.add_section("publish", "what the DDS front end publishes");
  s.add_string("publish.plans", "none", "publish each accepted plan", {"none", "dds"});
  s.add_section("dds", "Cyclone DDS (flipper dds; loopback-only by default)");
  s.add_int("dds.domain", 0, "DDS domain id", 0, 232);
  s.add_string_list("dds.interfaces", {}, "network interfaces (empty: loopback only)");
  s.add_string("dds.config", "", "a Cyclone DDS XML config (empty: the built-in one)");
  s.add_string("dds.namespace", "",
               "this node's ROS 2 namespace: topics rt/<namespace>/flipper/... (empty: "
               "rt/flipper/...)");
  s.add_path("dds.security.keystore", std::string(),
             "DDS Security: the folder of `flipper dds security init` (empty: security off)");
  s.add_string("dds.security.identity", "",
               "DDS Security: this participant's identity in the keystore (empty: lexicon.site, "
               "else dds.namespace)");

  s.add_section("induction", "grammar induction from definitions");
  add(s, keys::kAlignment);
  add(s, keys::kGeneralize);
  add(s, keys::kPerturbedChecks);
  s.add_section("execution", "limits of one program's execution");
  add(s, keys::kActionBudget);
  add(s, keys::kStepBudget);
  add(s, keys::kWhileLimit);
  add(s, keys::kExecCpuBudgetMs);
  add(s, keys::kExecDeadlineMs);
  s.add_retired("execution.time_budget_ms",
                "it was a wall-clock budget, so a result depended on the machine's load; results "
                "are bounded by work now (execution.action_budget, execution.step_budget) and "
                "by CPU time (execution.cpu_budget_ms), and the wall-clock limit is the far "
                "backstop execution.deadline_ms; either refuses the query (deadline_exceeded) "
                "instead of changing a plan (docs/planners.md §2)");
  s.add_section("input", "limits on what a request or a file may make the kernel do");
  add(s, keys::kMaxChars);
  add(s, keys::kMaxSemicolons);
  add(s, keys::kMaxLineBytes);
  add(s, keys::kMaxJsonDepth);
  add(s, keys::kMaxTokens);
  add(s, keys::kMaxBodyLines);
  add(s, keys::kMaxFileBytes);
  s.add_section("session", "one session's answers");
  add(s, keys::kSessionK);
  add(s, keys::kCpuBudgetMs);
  add(s, keys::kDeadlineMs);
  s.add_path_list("plugin_paths", {}, "more directories to find plugins in");
  s.add_section("plugins", "how plugin calls run");
  s.add_string(std::string(keys::kPluginIsolation.path), std::string(keys::kPluginIsolation.def),
               std::string(keys::kPluginIsolation.doc), {"auto", "in_process", "process"});

  s.add_section("serve", "flipper serve (Flipper Studio)");
  s.add_string(std::string(keys::kServeHost.path), std::string(keys::kServeHost.def),
               std::string(keys::kServeHost.doc));
  add(s, keys::kServePort);
  add(s, keys::kServeThreads);
  add(s, keys::kServeMaxRequestBytes);
  add(s, keys::kServeRatePerSecond);
  add(s, keys::kServeRateBurst);
  add(s, keys::kServeMaxSessions);
  add(s, keys::kServeSessionIdleS);
  s.add_path("serve.web_dir", std::string(), "the page's files (empty: the installed ones)");
  s.add_path("serve.study", std::string(), "a study description (empty: no study)");
  s.add_bool(std::string(keys::kServeSempre.path), keys::kServeSempre.def,
             "also answer the 2018 server's API at GET /sempre, to this page and "
             "serve.sempre_origins (docs/sempre.md)");
  s.add_string_list("serve.sempre_origins", {},
                    "web origins ('http://host:port') whose pages may use /sempre besides the "
                    "server's own; '*' every origin (docs/sempre.md)");
  s.add_string_list("serve.allowed_hosts", {},
                    "more Host names the server answers to ('name' or 'name:port')");
  s.add_path("serve.accounts", std::string(),
             "the accounts store (empty: accounts.sqlite beside lexicon.path)");
  add(s, keys::kServeGuests);
  add(s, keys::kServeLoginDays);
  add(s, keys::kServeRequestTimeoutMs);
  add(s, keys::kServeIdleTimeoutMs);
  add(s, keys::kServeMaxConnections);
  add(s, keys::kServeMaxConnectionsPerAddress);
  add(s, keys::kServeSessionsPerAddress);
  add(s, keys::kServeNewSessionsPerMinute);
  add(s, keys::kServeMemoryBudgetMb);
  add(s, keys::kServeEvictAfterS);
  s.add_int("serve.sessions_per_subnet", 128,
            "open guest sessions per /24 (IPv4) or /64 (IPv6) subnet: 429 beyond", 1, 1000000);
  s.add_int("serve.new_guests_per_minute", 600,
            "new guest sessions per minute, all addresses together: 503 beyond", 1, 1000000);
  s.add_int("serve.reserved_sessions_percent", 10,
            "per cent of serve.max_sessions that only logged-in users may open", 0, 90);
  s.add_int("serve.max_connections_per_subnet", 256,
            "open connections per /24 (IPv4) or /64 (IPv6) subnet: 503 beyond", 1, 1000000);
  add(s, keys::kServeCpuMsPerS);
  add(s, keys::kServeCpuBurstMs);
  add(s, keys::kServeKernels);
  return s;
}

}  // namespace

const sdk::ParamSchema& Config::schema() {
  static const ParamSchema kSchema = build();
  return kSchema;
}

}  // namespace flipper::kernel
