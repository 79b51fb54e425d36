// Known answers, worked out by hand, for the emulated passes whose other tests compare them with a
// reference implementation or with each other: trim, compress, sort, decompress, reduce, the cone
// union of build.parents, the triangle spheres of prep and the traversal's margin. No Vulkan; each
// input is small enough to check on paper.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"

using namespace rayspace;
using namespace rayspace::emu;

TEST_CASE("trim: known answer, four slots with the middle two flagged") {
  std::vector<layout::Ray> rays(4);
  for (std::uint32_t i = 0; i < 4; ++i) rays[i].info.w = 10 + i;
  const std::vector<std::uint32_t> flags = {0, 1, 1, 0};
  const Trimmed t = PassTrim({.kind = layout::kRayShadow, .rays = rays, .flags = flags});
  // Exclusive scan of the flags: 0, 0, 1, 2; the flagged slots 1 and 2 land at 0 and 1.
  CHECK(t.offsets == std::vector<std::uint32_t>{0, 0, 1, 2});
  REQUIRE(t.rays.size() == 2);
  CHECK(t.rays[0].info.w == 11);
  CHECK(t.rays[1].info.w == 12);
}

TEST_CASE("compress: known answer, runs of equal keys become chunks") {
  // Keys 5 5 3 3 3 9: three runs starting at 0, 2 and 5, of 2, 3 and 1 rays.
  const std::vector<std::uint32_t> keys = {5, 5, 3, 3, 3, 9};
  const Chunks c = PassCompress({.keys = keys});
  CHECK(c.key == std::vector<std::uint32_t>{5, 3, 9});
  CHECK(c.base == std::vector<std::uint32_t>{0, 2, 5});
  CHECK(c.size == std::vector<std::uint32_t>{2, 3, 1});
}

TEST_CASE("sort: known answer, a stable order by key over every byte") {
  // Keys 0x300, 1, 0x300, 0x2000000, 0: ascending 0 (4), 1 (1), 0x300 (0 before 2: stable), 0x2000000 (3).
  const std::vector<std::uint32_t> keys = {0x300, 1, 0x300, 0x2000000, 0};
  CHECK(PassSortChunks({.chunk_key = keys}) == std::vector<std::uint32_t>{4, 1, 0, 2, 3});
  // The top byte alone decides: 0x01000000 before 0x02000000 before 0xFF000000.
  const std::vector<std::uint32_t> top = {0xFF000000u, 0x02000000u, 0x01000000u};
  CHECK(PassSortChunks({.chunk_key = top}) == std::vector<std::uint32_t>{2, 1, 0});
}

TEST_CASE("decompress: known answer, the rays of each chunk in sorted chunk order") {
  // Chunks (key, base, size) = (5, 0, 2), (3, 2, 3), (9, 5, 1) sorted as 1, 0, 2: rays 2 3 4, 0 1, 5.
  const std::vector<std::uint32_t> key = {5, 3, 9}, base = {0, 2, 5}, size = {2, 3, 1}, order = {1, 0, 2};
  CHECK(PassDecompress({.chunk_key = key, .chunk_base = base, .chunk_size = size, .chunk_order = order}) ==
        std::vector<std::uint32_t>{2, 3, 4, 0, 1, 5});
}

TEST_CASE("reduce: known answer, the flagged values in slot order for every component size") {
  const std::vector<std::uint8_t> flags = {1, 0, 1, 1, 0, 0, 1};
  const std::vector<std::uint32_t> values = {10, 11, 12, 13, 14, 15, 16};
  const std::vector<std::uint32_t> expect = {10, 12, 13, 16};
  CHECK(PassReduce({.reduction = Reduction::kScan, .flags = flags, .values = values}) == expect);
  for (int s : {1, 2, 3, 4, 7, 64}) {
    INFO("component " << s);
    CHECK(PassReduce({.reduction = Reduction::kHierarchical, .component = s, .flags = flags, .values = values}) == expect);
  }
  // A component whose last slot is flagged, and one with none flagged.
  const std::vector<std::uint8_t> edge = {0, 1, 0, 0};
  CHECK(PassReduce({.reduction = Reduction::kHierarchical, .component = 2, .flags = edge, .values = values}) ==
        std::vector<std::uint32_t>{11});
}

TEST_CASE("cone union: known answer, two spheres and two narrow cones at right angles") {
  layout::ConeNode a{}, b{};
  a.sphere = {0, 0, 0, 1};
  b.sphere = {4, 0, 0, 2};
  a.cone = {1, 0, 0, 1};  // along x, half-angle 0: (cos, sin) = (1, 0)
  b.cone = {0, 1, 0, 1};  // along y
  a.extra = {0, 3, 0, 0};  // 3 rays
  b.extra = {0, 5, 0, 0};  // 5 rays
  const layout::ConeNode n = cone::Union(a, b);
  // Eqs. 3.14-3.15: the centres' midpoint (2, 0, 0), radius half their distance (2) plus the larger radius (2).
  CHECK(n.sphere.x == doctest::Approx(2.0f));
  CHECK(n.sphere.y == 0.0f);
  CHECK(n.sphere.z == 0.0f);
  CHECK(n.sphere.w == doctest::Approx(4.0f));
  // Eqs. 3.12-3.13: the axes' bisector (1, 1, 0) / sqrt 2 and half the 90 degrees between them.
  const float h = std::sqrt(0.5f);
  CHECK(n.cone.x == doctest::Approx(h));
  CHECK(n.cone.y == doctest::Approx(h));
  CHECK(n.cone.z == doctest::Approx(0.0f));
  CHECK(n.cone.w == doctest::Approx(h));   // cos 45 degrees
  CHECK(n.extra.x == doctest::Approx(h));  // sin 45 degrees
  CHECK(n.extra.y == 8.0f);                // the rays of both
  // A wider child widens the union by its own half-angle: 45 + 30 degrees.
  b.cone.w = std::cos(0.5235988f);
  b.extra.x = std::sin(0.5235988f);
  const layout::ConeNode w = cone::Union(a, b);
  CHECK(w.cone.w == doctest::Approx(std::cos(1.3089969f)).epsilon(1e-5));
  CHECK(w.extra.x == doctest::Approx(std::sin(1.3089969f)).epsilon(1e-5));
  // Antiparallel axes: only the full sphere of directions holds both.
  b.cone = {-1, 0, 0, 1};
  b.extra.x = 0;
  CHECK(cone::IsFull(cone::Union(a, b)));
}

TEST_CASE("prep: known answer, a triangle's sphere is its circumcircle when acute, its longest edge's when not") {
  std::vector<layout::Triangle> tris(2);
  // Acute (equilateral): the circumcentre (1/3, 1/3, 1/3), radius sqrt(2/3).
  tris[0].v0 = {1, 0, 0, 1};
  tris[0].v1 = {0, 1, 0, 1};
  tris[0].v2 = {0, 0, 1, 1};
  // Right angle at the origin: the hypotenuse's midpoint (2, 1.5, 0), radius 2.5.
  tris[1].v0 = {0, 0, 0, 1};
  tris[1].v1 = {4, 0, 0, 1};
  tris[1].v2 = {0, 3, 0, 1};
  const std::vector<glm::vec4> s = PassTriangleSpheres(tris);
  REQUIRE(s.size() == 2);
  for (int k = 0; k < 3; ++k) CHECK(s[0][k] == doctest::Approx(1.0 / 3.0).epsilon(1e-6));
  CHECK(s[0].w == doctest::Approx(std::sqrt(2.0 / 3.0)).epsilon(1e-5));
  CHECK(s[0].w >= std::sqrt(2.0f / 3.0f));  // rounded outward
  CHECK(s[1].x == 2.0f);
  CHECK(s[1].y == 1.5f);
  CHECK(s[1].z == 0.0f);
  CHECK(s[1].w == doctest::Approx(2.5).epsilon(1e-5));
  CHECK(s[1].w >= 2.5f);
}

TEST_CASE("traverse: known answer, the cone test's margin is a millionth of the scene's diagonal") {
  SceneBuffers b;
  b.lo = {1, 1, 1};
  b.hi = {4, 5, 1};  // diagonal (3, 4, 0): length 5
  CHECK(TraversalEpsilon(b) == doctest::Approx(5e-6).epsilon(1e-6));
}
