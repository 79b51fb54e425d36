// grid.trace's eye rays in tiled z-buffer order, for PassGridTraceLanes (grid_eye_tiles.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/grid/grid.h"

namespace rayspace::emu {

// Traces a closest-hit batch's eye rays that go through the eye's grid (--primary grid) per cell and
// per triangle, writing their hits, steps and tests into `out` (sized for every ray) as the pass
// would; returns per ray whether it was traced here (the rest walk ray by ray). None without an
// eye grid, in a shadow batch, or with scalar lanes.
std::vector<std::uint8_t> TraceEyeTiles(const call::GridTrace& c, const GridLanes& lanes, GridWalks& out);


}  // namespace rayspace::emu
