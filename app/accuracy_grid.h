// `rayspace accuracy`, the perspective grids' binning (docs/grids.md): the `--algo grid` frame with the
// binning's rounding margins and without them, against the direct tracer (the same watertight test
// over every triangle), ray by ray.
#pragma once
#include <vector>

#include "accuracy_measure.h"
#include "rayspace/emu/frame.h"
#include "rayspace/scene.h"

namespace rayspace::app::accuracy {

std::vector<EndToEnd> GridEndToEnd(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo);

}  // namespace rayspace::app::accuracy
