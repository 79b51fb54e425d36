// Named comparators for buffers produced by two backends. Buffers are compared 32-bit word by word;
// a per-element mask says which words hold floats (for ULP distances and NaN classes).
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace rayspace {

struct BufferComparison {
  std::string pass, buffer;
  std::size_t elements = 0;         // elements compared (the shorter length when sizes differ)
  std::size_t expected_elements = 0, actual_elements = 0;
  std::size_t mismatches = 0;       // elements with at least one differing word
  std::size_t nan_class_matches = 0;  // float words that are NaN on both sides (payloads not compared)
  bool has_float = false;
  std::uint64_t max_ulp = 0;        // largest ULP distance over differing float words
  // First mismatching element: its index, the first differing word in it, both values.
  std::size_t first_index = 0, first_word = 0;
  std::uint32_t first_expected = 0, first_actual = 0;
  bool first_is_float = false;
  // When sizes differ: the longer side's first element past the common ones (its first word).
  std::uint32_t first_extra = 0;
  bool first_extra_is_float = false;
  // Which side computed each buffer (diff: the emulator and the Vulkan kernels), named in Summary and
  // in the JSON beside the values.
  std::string expected_name = "expected", actual_name = "actual";
  bool Equal() const { return mismatches == 0 && expected_elements == actual_elements; }
  void ToJson(nlohmann::json& j) const;
  std::string Summary() const;
};

// ULP distance between two finite-or-infinite floats given as bits (0 for +0 vs -0).
std::uint64_t UlpDistance(std::uint32_t a, std::uint32_t b);

// Compares word by word. `words` per element; bit k of `float_mask` set when word k is a float.
BufferComparison CompareWords(const std::string& pass, const std::string& buffer, std::span<const std::uint32_t> expected,
                              std::span<const std::uint32_t> actual, std::size_t words, std::uint32_t float_mask);
// Compares a byte buffer element by element (each byte reported as the word it widens to).
BufferComparison CompareBytes(const std::string& pass, const std::string& buffer, std::span<const std::uint8_t> expected,
                              std::span<const std::uint8_t> actual);

template <typename T>
BufferComparison CompareBuffers(const std::string& pass, const std::string& buffer, const std::vector<T>& expected,
                                const std::vector<T>& actual, std::uint32_t float_mask) {
  static_assert(sizeof(T) % 4 == 0);
  return CompareWords(pass, buffer,
                      std::span(reinterpret_cast<const std::uint32_t*>(expected.data()), expected.size() * sizeof(T) / 4),
                      std::span(reinterpret_cast<const std::uint32_t*>(actual.data()), actual.size() * sizeof(T) / 4),
                      sizeof(T) / 4, float_mask);
}

}  // namespace rayspace
