// The frame of one reproduce configuration, rendered as `rayspace render` renders it (oracle off: the
// frames are verified by the test suite), its statistics in the thesis's terms.
#pragma once
#include "rayspace/reproduce/runner.h"

namespace rayspace::reproduce {

FrameOutput RenderConfig(const Config& config, const Scene& scene, const SceneBuffers& buffers);

}  // namespace rayspace::reproduce
