// `rayspace accuracy`, the perspective grids' binning (docs/grids.md): the `--algo grid` frame with the
// binning's rounding margins and without them, against the direct tracer (the same watertight test
// over every triangle), ray by ray.
#pragma once
#include <vector>

#include "rayspace/accuracy/measure.h"
#include "rayspace/emu/frame.h"
#include "rayspace/scene.h"

namespace rayspace::accuracy {

std::vector<EndToEnd> GridEndToEnd(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo);

}  // namespace rayspace::accuracy
