// A diverged pair list is reported as the candidate pairs one side lost and added (multisets, the
// order of the list aside), the first of each decoded into its node and triangle.
#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "rayspace/layout.h"
#include "rayspace/verify/differ.h"

using rayspace::verify::PairBases;
using rayspace::verify::PairsChanged;

namespace {

std::uint32_t Pack(std::uint32_t node, std::uint32_t tri) { return node << rayspace::layout::kPairTriangleBits | tri; }

}  // namespace

TEST_CASE("pairs changed: one lost pair is counted and named, never called harmless") {
  const std::vector<std::uint32_t> e = {Pack(0, 5), Pack(3, 7), Pack(3, 9)};
  const std::vector<std::uint32_t> a = {Pack(0, 5), Pack(3, 9)};
  const std::string s = PairsChanged(e, a, PairBases{100, 2000});
  CHECK(s == "1 of the reference's 3 candidate pairs lost, 0 added; first lost: (node 103, triangle 2007); a lost pair may "
             "hold a hit (not judged)");
}

TEST_CASE("pairs changed: an added pair and a lost one, without bases as offsets, a duplicate counting") {
  const std::vector<std::uint32_t> e = {Pack(1, 1), Pack(1, 1), Pack(2, 2)};
  const std::vector<std::uint32_t> a = {Pack(1, 1), Pack(2, 2), Pack(4, 0)};
  const std::string s = PairsChanged(e, a, std::nullopt);
  CHECK(s == "1 of the reference's 3 candidate pairs lost, 1 added; first lost: (node +1, triangle +1 from the level's and "
             "the batch's first); first added: (node +4, triangle +0 from the level's and the batch's first); a lost pair "
             "may hold a hit (not judged)");
}

TEST_CASE("pairs changed: the same pairs in another order are named so") {
  const std::vector<std::uint32_t> e = {Pack(1, 2), Pack(3, 4)};
  const std::vector<std::uint32_t> a = {Pack(3, 4), Pack(1, 2)};
  CHECK(PairsChanged(e, a, PairBases{}) == "the same 2 candidate pairs in another order");
}
