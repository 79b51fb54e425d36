#include "rayspace/compare.h"

#include <cstring>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace rayspace {
namespace {

bool IsNan(std::uint32_t b) { return (b & 0x7F800000u) == 0x7F800000u && (b & 0x007FFFFFu) != 0; }

// Maps float bits to integers that order like the floats (-0 and +0 both map to 0).
std::int64_t Ordered(std::uint32_t b) {
  const std::int64_t mag = b & 0x7FFFFFFFu;
  return (b & 0x80000000u) ? -mag : mag;
}

std::string Show(std::uint32_t w, bool is_float) {
  if (!is_float) return fmt::format("0x{:08x} ({})", w, w);
  float f;
  std::memcpy(&f, &w, 4);
  return fmt::format("0x{:08x} ({:.9g})", w, f);
}

}  // namespace

std::uint64_t UlpDistance(std::uint32_t a, std::uint32_t b) {
  const std::int64_t d = Ordered(a) - Ordered(b);
  return static_cast<std::uint64_t>(d < 0 ? -d : d);
}

namespace {

// Word is std::uint32_t for word buffers and std::uint8_t for byte buffers (one word per element,
// no floats): bytes are compared as the words they widen to, without widening a copy.
template <typename Word>
BufferComparison CompareImpl(const std::string& pass, const std::string& buffer, std::span<const Word> expected,
                             std::span<const Word> actual, std::size_t words, std::uint32_t float_mask) {
  BufferComparison c;
  c.pass = pass;
  c.buffer = buffer;
  c.has_float = float_mask != 0;
  c.expected_elements = expected.size() / words;
  c.actual_elements = actual.size() / words;
  c.elements = std::min(c.expected_elements, c.actual_elements);
  // Equal buffers, the usual case, in one memcmp: the loop below would find nothing to record.
  if (expected.size() == actual.size() &&
      (expected.empty() || std::memcmp(expected.data(), actual.data(), expected.size_bytes()) == 0))
    return c;
  for (std::size_t e = 0; e < c.elements; ++e) {
    bool differs = false;
    for (std::size_t w = 0; w < words; ++w) {
      const std::uint32_t x = expected[e * words + w], y = actual[e * words + w];
      const bool is_float = (float_mask >> w) & 1u;
      if (x == y) continue;
      if (is_float && IsNan(x) && IsNan(y)) {  // NaN payloads are not reproducible: compare the class
        ++c.nan_class_matches;
        continue;
      }
      if (is_float && !IsNan(x) && !IsNan(y)) c.max_ulp = std::max(c.max_ulp, UlpDistance(x, y));
      if (!differs && c.mismatches == 0) {
        c.first_index = e;
        c.first_word = w;
        c.first_expected = x;
        c.first_actual = y;
        c.first_is_float = is_float;
      }
      differs = true;
    }
    c.mismatches += differs;
  }
  if (c.expected_elements != c.actual_elements) {
    const std::span<const Word> longer = c.expected_elements > c.actual_elements ? expected : actual;
    c.first_extra = longer[c.elements * words];
    c.first_extra_is_float = float_mask & 1u;
  }
  return c;
}

}  // namespace

BufferComparison CompareWords(const std::string& pass, const std::string& buffer, std::span<const std::uint32_t> expected,
                              std::span<const std::uint32_t> actual, std::size_t words, std::uint32_t float_mask) {
  return CompareImpl(pass, buffer, expected, actual, words, float_mask);
}

BufferComparison CompareBytes(const std::string& pass, const std::string& buffer, std::span<const std::uint8_t> expected,
                              std::span<const std::uint8_t> actual) {
  return CompareImpl(pass, buffer, expected, actual, 1, 0);
}

std::string BufferComparison::Summary() const {
  if (Equal()) return fmt::format("{}/{}: {} elements equal", pass, buffer, elements);
  const std::string first = fmt::format("first at {} (word {}): {} {}, {} {}{}", first_index, first_word, expected_name,
                                        Show(first_expected, first_is_float), actual_name, Show(first_actual, first_is_float),
                                        has_float ? fmt::format(", max {} ULP", max_ulp) : "");
  if (expected_elements == actual_elements)
    return fmt::format("{}/{}: {} of {} elements differ; {}", pass, buffer, mismatches, elements, first);
  // Sizes differ: the common elements compared too, and where the longer side goes on.
  const std::string sizes = fmt::format("{}/{}: sizes differ ({} {} elements, {} {})", pass, buffer, expected_name,
                                        expected_elements, actual_name, actual_elements);
  const std::string extra = fmt::format("{} goes on at {} with {}", expected_elements > actual_elements ? expected_name : actual_name,
                                        elements, Show(first_extra, first_extra_is_float));
  if (mismatches == 0) return fmt::format("{}; the {} in common are equal; {}", sizes, elements, extra);
  return fmt::format("{}; {} of the {} in common differ, {}; {}", sizes, mismatches, elements, first, extra);
}

void BufferComparison::ToJson(nlohmann::json& j) const {
  j = {{"pass", pass}, {"buffer", buffer}, {"elements", elements}, {"expected_elements", expected_elements},
       {"actual_elements", actual_elements}, {"mismatches", mismatches}, {"equal", Equal()},
       {"expected_backend", expected_name}, {"actual_backend", actual_name}};
  if (has_float) {
    j["max_ulp"] = max_ulp;
    j["nan_class_matches"] = nan_class_matches;
  }
  if (expected_elements != actual_elements)
    j["first_extra"] = {{"index", elements},
                        {"backend", expected_elements > actual_elements ? expected_name : actual_name},
                        {"value", Show(first_extra, first_extra_is_float)}};
  if (mismatches)
    j["first_mismatch"] = {{"index", first_index}, {"word", first_word},
                           {"expected", Show(first_expected, first_is_float)},
                           {"actual", Show(first_actual, first_is_float)}};
}

}  // namespace rayspace
