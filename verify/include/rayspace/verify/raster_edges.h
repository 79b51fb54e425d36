// Where a diverged raster differs. Vulkan's rasterization rules fix which pixels a triangle covers
// only up to the device's sub-pixel precision and snapping, so a device other than lavapipe may
// legitimately cover an edge pixel the emulator does not (or the reverse); a difference inside a
// triangle, away from every edge, is a bug on any device.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace rayspace::verify {

struct RasterDifference {
  std::size_t pixels = 0;  // pixels where the primitive id or the depth differs
  std::size_t edge = 0;    // of those, pixels with a neighbour (8-connected) of another primitive in either image
                           // (either: a sliver one image misses entirely is an edge in the other)
  std::size_t interior() const { return pixels - edge; }
  std::string Summary() const;  // "N pixels differ: E on a triangle edge (...), I interior (...)"
};

// Whether pixel (x, y) has a neighbour (8-connected) of another primitive in either image.
bool OnTriangleEdge(std::uint32_t width, std::uint32_t height, std::span<const std::uint32_t> expected_prim,
                    std::span<const std::uint32_t> actual_prim, std::uint32_t x, std::uint32_t y);

// Compares the two G-buffers of a width x height raster by primitive id and depth bits.
RasterDifference ClassifyRaster(std::uint32_t width, std::uint32_t height, std::span<const std::uint32_t> expected_prim,
                                std::span<const std::uint32_t> actual_prim, std::span<const float> expected_depth,
                                std::span<const float> actual_depth);

}  // namespace rayspace::verify
