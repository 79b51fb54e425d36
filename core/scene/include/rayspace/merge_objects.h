// A scene's objects merged into one, as the CRSH thesis loaded Sponza ("not divided into
// submeshes"): the hierarchy tracers then cull against one bounding sphere instead of one per object.
#pragma once
#include "rayspace/scene_buffers.h"

namespace rayspace {

// Makes `b` one object of all its triangles, in their order; each triangle keeps its material. The
// hits do not change, only which object spheres the traversal tests.
void MergeObjects(SceneBuffers& b);

}  // namespace rayspace
