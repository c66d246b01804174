#include "elf_check.hpp"

#include <elf.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <vector>

#include "flipper/sdk/errors.hpp"

namespace flipper::sdk::detail {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& why) {
  throw sdk::Error(sdk::codes::kPluginLoadFailed,
                   "cannot load plugin library '" + path + "': " + why);
}

struct File {
  int fd = -1;
  ~File() {
    if (fd >= 0) ::close(fd);
  }
};

// Reads exactly `n` bytes at `offset`; false if the file is shorter.
bool read_at(int fd, void* buf, std::size_t n, std::uint64_t offset) {
  auto* p = static_cast<char*>(buf);
  while (n > 0) {
    const ssize_t got = ::pread(fd, p, n, static_cast<off_t>(offset));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    p += got;
    n -= static_cast<std::size_t>(got);
    offset += static_cast<std::uint64_t>(got);
  }
  return true;
}

// offset + count * size <= file size, without overflow.
bool fits(std::uint64_t offset, std::uint64_t count, std::uint64_t size, std::uint64_t file) {
  if (offset > file) return false;
  if (count == 0 || size == 0) return true;
  return count <= (file - offset) / size;
}

std::string bytes_range(std::uint64_t offset, std::uint64_t length, std::uint64_t file) {
  return "bytes " + std::to_string(offset) + ".." + std::to_string(offset + length) +
         " but the file has " + std::to_string(file) + " bytes: truncated or damaged";
}

}  // namespace

void check_elf_file(const std::string& path) {
  File f;
  f.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (f.fd < 0) fail(path, std::strerror(errno));
  struct stat st {};
  if (::fstat(f.fd, &st) != 0) fail(path, std::strerror(errno));
  if (!S_ISREG(st.st_mode)) fail(path, "not a regular file");
  const auto file = static_cast<std::uint64_t>(st.st_size);

  Elf64_Ehdr eh{};
  if (!read_at(f.fd, &eh, sizeof eh, 0))
    fail(path, "not an ELF shared library (" + std::to_string(file) + " bytes, truncated)");
  if (std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0) fail(path, "not an ELF file");
  if (eh.e_ident[EI_CLASS] != ELFCLASS64) fail(path, "not a 64-bit ELF file");
  if (eh.e_type != ET_DYN) fail(path, "not an ELF shared library");

  if (eh.e_phnum > 0 && eh.e_phentsize != sizeof(Elf64_Phdr)) fail(path, "bad program headers");
  if (!fits(eh.e_phoff, eh.e_phnum, sizeof(Elf64_Phdr), file))
    fail(path, "program headers at " +
                   bytes_range(eh.e_phoff, std::uint64_t{eh.e_phnum} * sizeof(Elf64_Phdr), file));
  std::vector<Elf64_Phdr> ph(eh.e_phnum);
  if (!ph.empty() && !read_at(f.fd, ph.data(), ph.size() * sizeof(Elf64_Phdr), eh.e_phoff))
    fail(path, "cannot read the program headers");
  for (std::size_t i = 0; i < ph.size(); ++i)
    if (ph[i].p_type == PT_LOAD && !fits(ph[i].p_offset, 1, ph[i].p_filesz, file))
      fail(path, "segment " + std::to_string(i) + " at " +
                     bytes_range(ph[i].p_offset, ph[i].p_filesz, file));

  if (eh.e_shoff == 0 || eh.e_shnum == 0) return;
  if (eh.e_shentsize != sizeof(Elf64_Shdr)) fail(path, "bad section headers");
  if (!fits(eh.e_shoff, eh.e_shnum, sizeof(Elf64_Shdr), file))
    fail(path, "section headers at " +
                   bytes_range(eh.e_shoff, std::uint64_t{eh.e_shnum} * sizeof(Elf64_Shdr), file));
  std::vector<Elf64_Shdr> sh(eh.e_shnum);
  if (!read_at(f.fd, sh.data(), sh.size() * sizeof(Elf64_Shdr), eh.e_shoff))
    fail(path, "cannot read the section headers");
  for (std::size_t i = 0; i < sh.size(); ++i)
    if (sh[i].sh_type != SHT_NOBITS && !fits(sh[i].sh_offset, 1, sh[i].sh_size, file))
      fail(path, "section " + std::to_string(i) + " at " +
                     bytes_range(sh[i].sh_offset, sh[i].sh_size, file));
}

}  // namespace flipper::sdk::detail
