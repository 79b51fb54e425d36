// The named comparators (core compare.h) on buffers whose differences are known: element and word of
// the first mismatch, ULP distances, NaN classes, size differences, and bytes reported as the words
// they widen to. Equal buffers take a shortcut; it must report what the element loop would.
#include <doctest/doctest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

#include "rayspace/compare.h"

using namespace rayspace;

namespace {

std::uint32_t Bits(float f) { return std::bit_cast<std::uint32_t>(f); }

}  // namespace

TEST_CASE("CompareWords: the first differing element and word, its values and the largest ULP distance") {
  // Two elements of two words: word 0 a float, word 1 an integer.
  const std::vector<std::uint32_t> e = {Bits(1.0f), 5, Bits(2.0f), 6};
  std::vector<std::uint32_t> a = e;
  a[2] = Bits(2.0f) + 3;  // element 1, word 0: 3 ULP
  a[3] = 7;               // element 1, word 1
  const BufferComparison c = CompareWords("p", "b", e, a, 2, 0x1);
  CHECK_FALSE(c.Equal());
  CHECK(c.elements == 2);
  CHECK(c.mismatches == 1);
  CHECK(c.first_index == 1);
  CHECK(c.first_word == 0);
  CHECK(c.first_expected == Bits(2.0f));
  CHECK(c.first_actual == Bits(2.0f) + 3);
  CHECK(c.first_is_float);
  CHECK(c.max_ulp == 3);
  CHECK(c.Summary() == "p/b: 1 of 2 elements differ; first at 1 (word 0): expected 0x40000000 (2), actual 0x40000003 "
                       "(2.00000072), max 3 ULP");
}

TEST_CASE("CompareWords: NaNs of different payloads match by class; -0 and +0 are 0 ULP apart but differ") {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<std::uint32_t> e = {Bits(nan), Bits(0.0f)};
  const std::vector<std::uint32_t> a = {Bits(nan) | 1u, Bits(-0.0f)};
  const BufferComparison c = CompareWords("p", "b", e, a, 1, 0x1);
  CHECK(c.nan_class_matches == 1);
  CHECK(c.mismatches == 1);
  CHECK(c.first_index == 1);
  CHECK(c.max_ulp == 0);
  CHECK(UlpDistance(Bits(1.0f), Bits(-1.0f)) == 2 * std::uint64_t{Bits(1.0f)});
}

TEST_CASE("CompareWords: equal buffers count their elements; buffers of other lengths are unequal") {
  const std::vector<std::uint32_t> e = {1, 2, 3, 4, 5, 6};
  const BufferComparison same = CompareWords("p", "b", e, e, 3, 0);
  CHECK(same.Equal());
  CHECK(same.elements == 2);
  CHECK(same.expected_elements == 2);
  CHECK(same.mismatches == 0);
  const std::vector<std::uint32_t> longer = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  const BufferComparison c = CompareWords("p", "b", e, longer, 3, 0);
  CHECK_FALSE(c.Equal());
  CHECK(c.mismatches == 0);
  CHECK(c.elements == 2);
  CHECK(c.actual_elements == 3);
  CHECK(c.Summary() == "p/b: sizes differ (expected 2 elements, actual 3); the 2 in common are equal; actual goes on at 2 with 0x00000007 (7)");
  // A difference inside the common elements is reported too, not hidden by the sizes.
  std::vector<std::uint32_t> shorter = {1, 2, 3, 4, 0, 6};
  const BufferComparison d = CompareWords("p", "b", longer, shorter, 3, 0);
  CHECK(d.mismatches == 1);
  CHECK(d.Summary() ==
        "p/b: sizes differ (expected 3 elements, actual 2); 1 of the 2 in common differ, first at 1 (word 1): expected 0x00000005 (5), "
        "actual 0x00000000 (0); expected goes on at 2 with 0x00000007 (7)");
}

TEST_CASE("CompareBytes: each byte is an element, reported as its word") {
  const std::vector<std::uint8_t> e = {0, 1, 2, 255, 4};
  std::vector<std::uint8_t> a = e;
  CHECK(CompareBytes("p", "flags", e, a).Equal());
  CHECK(CompareBytes("p", "flags", e, a).elements == 5);
  a[3] = 0;
  a[4] = 9;
  const BufferComparison c = CompareBytes("p", "flags", e, a);
  CHECK(c.mismatches == 2);
  CHECK(c.first_index == 3);
  CHECK(c.first_expected == 255);
  CHECK(c.first_actual == 0);
  CHECK_FALSE(c.has_float);
}
