#include "rayspace/verify/raster_edges.h"

#include <bit>

#include <fmt/format.h>

namespace rayspace::verify {

std::string RasterDifference::Summary() const {
  return fmt::format("{} pixel(s) differ: {} on a triangle edge (where the rasterization rules let devices differ), "
                     "{} interior (a bug on any device)",
                     pixels, edge, interior());
}

RasterDifference ClassifyRaster(std::uint32_t width, std::uint32_t height, std::span<const std::uint32_t> expected_prim,
                                std::span<const std::uint32_t> actual_prim, std::span<const float> expected_depth,
                                std::span<const float> actual_depth) {
  RasterDifference d;
  const std::size_t n = std::size_t{width} * height;
  if (expected_prim.size() < n || actual_prim.size() < n || expected_depth.size() < n || actual_depth.size() < n) return d;
  for (std::uint32_t y = 0; y < height; ++y)
    for (std::uint32_t x = 0; x < width; ++x) {
      const std::size_t i = std::size_t{y} * width + x;
      if (expected_prim[i] == actual_prim[i] &&
          std::bit_cast<std::uint32_t>(expected_depth[i]) == std::bit_cast<std::uint32_t>(actual_depth[i]))
        continue;
      ++d.pixels;
      d.edge += OnTriangleEdge(width, height, expected_prim, actual_prim, x, y);
    }
  return d;
}

bool OnTriangleEdge(std::uint32_t width, std::uint32_t height, std::span<const std::uint32_t> expected_prim,
                    std::span<const std::uint32_t> actual_prim, std::uint32_t x, std::uint32_t y) {
  const std::size_t i = std::size_t{y} * width + x;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const std::int64_t nx = std::int64_t{x} + dx, ny = std::int64_t{y} + dy;
      if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
      const std::size_t j = static_cast<std::size_t>(ny) * width + static_cast<std::size_t>(nx);
      if (expected_prim[j] != expected_prim[i] || actual_prim[j] != actual_prim[i]) return true;
    }
  return false;
}

}  // namespace rayspace::verify
