#include "rayspace/digest.h"

#include <fmt/format.h>
#include <xxhash.h>

namespace rayspace {

std::uint64_t HashBytes(const void* data, std::size_t size, std::uint64_t seed) {
  return XXH3_64bits_withSeed(data, size, seed);
}

std::string HexDigest(std::uint64_t h) { return fmt::format("{:016x}", h); }

void DigestLog::AddBytes(std::string_view pass, std::string_view buffer, const void* data, std::size_t size) {
  entries_.push_back({std::string(pass), std::string(buffer), size, HashBytes(data, size)});
}

std::uint64_t DigestLog::Frame() const {
  XXH3_state_t* state = XXH3_createState();
  XXH3_64bits_reset(state);
  for (const Entry& e : entries_) {
    // Names are NUL-terminated in the stream so ("ab", "c") and ("a", "bc") hash differently.
    XXH3_64bits_update(state, e.pass.c_str(), e.pass.size() + 1);
    XXH3_64bits_update(state, e.buffer.c_str(), e.buffer.size() + 1);
    XXH3_64bits_update(state, &e.bytes, sizeof e.bytes);
    XXH3_64bits_update(state, &e.hash, sizeof e.hash);
  }
  const std::uint64_t h = XXH3_64bits_digest(state);
  XXH3_freeState(state);
  return h;
}

}  // namespace rayspace
