#pragma once
// flipper and flipper-frontends (CMakeLists.txt here): `flipper` links no network stack; `serve`
// and the DDS services run in <exe>/../libexec/flipper-frontends, which flipper execs with its
// own arguments. The two binaries share every subcommand's definition; they differ in the files
// that implement enter(), run_serve(), run_dds_node() and DdsServices (frontend_launch.cpp in
// flipper; frontend_entry.cpp, serve_run.cpp, dds_run.cpp, dds_services.cpp in the other).

namespace flipper::cli {

/// Set by flipper for the program it execs, which refuses to run under another tag (a partial
/// or mixed install). Bump the number when what flipper hands over changes.
inline constexpr const char* kFrontendsEnv = "FLIPPER_FRONTENDS_TAG";
inline constexpr const char* kFrontendsTag = "flipper " FLIPPER_VERSION " frontends/1";

/// main() hands over its arguments before parsing: flipper keeps them to exec
/// flipper-frontends; flipper-frontends checks the tag flipper set (exits 1 on a mismatch).
void enter(int argc, char** argv);

}  // namespace flipper::cli
