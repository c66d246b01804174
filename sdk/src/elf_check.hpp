#pragma once
// Checking a shared library's ELF structure before dlopen maps it: a truncated .so on the search
// path would otherwise map pages past the end of the file and die of SIGBUS on first touch.
#include <string>

namespace flipper::sdk::detail {

/// Reads (never maps) the ELF header, program headers and section headers of `path` and checks
/// that the file is a regular 64-bit ELF file and that every header, segment and section it
/// declares lies inside the file. Throws sdk::Error(plugin_load_failed) naming the file and the
/// first part that does not fit.
void check_elf_file(const std::string& path);

}  // namespace flipper::sdk::detail
