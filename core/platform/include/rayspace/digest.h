// Content hashes of pass outputs. A frame's digest covers every buffer every pass wrote, so two runs
// with the same digest produced the same bits everywhere.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rayspace {

std::uint64_t HashBytes(const void* data, std::size_t size, std::uint64_t seed = 0);

template <typename T>
std::uint64_t HashBuffer(std::span<const T> s) {
  return HashBytes(s.data(), s.size_bytes());
}

std::string HexDigest(std::uint64_t h);

// Ordered list of (pass, buffer, hash); the frame digest hashes the list in order.
class DigestLog {
 public:
  struct Entry {
    std::string pass;
    std::string buffer;
    std::size_t bytes;
    std::uint64_t hash;
  };
  template <typename T>
  void Add(std::string_view pass, std::string_view buffer, const std::vector<T>& v) {
    AddBytes(pass, buffer, v.data(), v.size() * sizeof(T));
  }
  void AddBytes(std::string_view pass, std::string_view buffer, const void* data, std::size_t size);
  std::uint64_t Frame() const;
  const std::vector<Entry>& entries() const { return entries_; }

 private:
  std::vector<Entry> entries_;
};

}  // namespace rayspace
