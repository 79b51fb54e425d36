// The diff's raster classification: a differing pixel next to another primitive (in either image) is
// an edge pixel, where devices may differ; one surrounded by its own primitive is interior.
#include <doctest/doctest.h>

#include <vector>

#include "rayspace/verify/raster_edges.h"

using namespace rayspace;

TEST_CASE("raster edges: known answers on a 6x4 image of two triangles") {
  // prim 1 in columns 0-2, prim 2 in columns 3-5.
  std::vector<std::uint32_t> prim(24);
  for (int i = 0; i < 24; ++i) prim[i] = i % 6 < 3 ? 1u : 2u;
  const std::vector<float> depth(24, 0.5f);
  SUBCASE("equal images: nothing differs") {
    const verify::RasterDifference d = verify::ClassifyRaster(6, 4, prim, prim, depth, depth);
    CHECK(d.pixels == 0);
  }
  SUBCASE("the boundary column moved: edge pixels") {
    std::vector<std::uint32_t> shifted = prim;
    for (int y = 0; y < 4; ++y) shifted[y * 6 + 3] = 1u;
    const verify::RasterDifference d = verify::ClassifyRaster(6, 4, prim, shifted, depth, depth);
    CHECK(d.pixels == 4);
    CHECK(d.edge == 4);
  }
  SUBCASE("a depth changed at a pixel whose neighbours all show its triangle: interior") {
    std::vector<float> deeper = depth;
    deeper[1 * 6 + 0] = 0.25f;  // column 0: neighbours in columns 0-1 are prim 1
    const verify::RasterDifference d = verify::ClassifyRaster(6, 4, prim, prim, depth, deeper);
    CHECK(d.pixels == 1);
    CHECK(d.interior() == 1);
  }
  SUBCASE("a sliver the expected image misses, inside a triangle: an edge in the actual image") {
    std::vector<std::uint32_t> sliver = prim;
    sliver[2 * 6 + 0] = 7u;
    const verify::RasterDifference d = verify::ClassifyRaster(6, 4, prim, sliver, depth, depth);
    CHECK(d.edge == 1);
  }
}
