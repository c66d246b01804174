// SHA-256 with GNU Nettle (nettle-dev): streamed in 64 KiB blocks, so large corpus files cost no
// more memory than small ones.
#include "flipper/record/checksum.hpp"

#include <nettle/sha2.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "flipper/sdk/errors.hpp"

namespace flipper::record {
namespace {

std::string hex(const std::array<std::uint8_t, SHA256_DIGEST_SIZE>& digest) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  out.reserve(2 * digest.size());
  for (std::uint8_t b : digest) {
    out += digits[b >> 4];
    out += digits[b & 15];
  }
  return out;
}

}  // namespace

std::string sha256_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw sdk::Error(sdk::codes::kBadRequest,
                     "cannot read '" + path + "' to checksum it: " + std::strerror(errno));
  sha256_ctx ctx;
  sha256_init(&ctx);
  std::array<char, 65536> buffer{};
  while (in) {
    in.read(buffer.data(), buffer.size());
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n > 0) sha256_update(&ctx, n, reinterpret_cast<const std::uint8_t*>(buffer.data()));
  }
  if (in.bad()) throw sdk::Error(sdk::codes::kBadRequest, "cannot read '" + path + "'");
  std::array<std::uint8_t, SHA256_DIGEST_SIZE> digest{};
  sha256_digest(&ctx, digest.size(), digest.data());
  return hex(digest);
}

std::string sha256_text(const std::string& text) {
  sha256_ctx ctx;
  sha256_init(&ctx);
  sha256_update(&ctx, text.size(), reinterpret_cast<const std::uint8_t*>(text.data()));
  std::array<std::uint8_t, SHA256_DIGEST_SIZE> digest{};
  sha256_digest(&ctx, digest.size(), digest.data());
  return hex(digest);
}

}  // namespace flipper::record
