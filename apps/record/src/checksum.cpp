// SHA-256 with libsodium (libsodium-dev, crypto_hash_sha256): streamed in 64 KiB blocks, so large
// corpus files cost no more memory than small ones.
#include "flipper/record/checksum.hpp"

#include <sodium.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "flipper/sdk/errors.hpp"

namespace flipper::record {
namespace {

using Digest = std::array<unsigned char, crypto_hash_sha256_BYTES>;

std::string hex(const Digest& digest) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  out.reserve(2 * digest.size());
  for (const unsigned char b : digest) {
    out += digits[b >> 4];
    out += digits[b & 15];
  }
  return out;
}

// libsodium's functions may be called only after sodium_init (thread-safe, idempotent); -1 means
// the library could not initialise (no randomness source), which the hash itself does not need.
void init_sodium() {
  static const int once = sodium_init();
  (void)once;
}

}  // namespace

std::string sha256_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw sdk::Error(sdk::codes::kBadRequest,
                     "cannot read '" + path + "' to checksum it: " + std::strerror(errno));
  init_sodium();
  crypto_hash_sha256_state state;
  crypto_hash_sha256_init(&state);
  std::array<char, 65536> buffer{};
  while (in) {
    in.read(buffer.data(), buffer.size());
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n > 0)
      crypto_hash_sha256_update(&state, reinterpret_cast<const unsigned char*>(buffer.data()), n);
  }
  if (in.bad()) throw sdk::Error(sdk::codes::kBadRequest, "cannot read '" + path + "'");
  Digest digest{};
  crypto_hash_sha256_final(&state, digest.data());
  return hex(digest);
}

std::string sha256_text(const std::string& text) {
  init_sodium();
  Digest digest{};
  crypto_hash_sha256(digest.data(), reinterpret_cast<const unsigned char*>(text.data()),
                     text.size());
  return hex(digest);
}

}  // namespace flipper::record
