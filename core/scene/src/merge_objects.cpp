#include "rayspace/merge_objects.h"

namespace rayspace {

void MergeObjects(SceneBuffers& b) {
  if (b.objects.size() <= 1) return;
  // FlattenScene lays objects' triangles out consecutively from 0, so the merged object is all of them.
  b.objects.assign(1, glm::uvec4(0u, static_cast<std::uint32_t>(b.triangles.size()), 0u, 0u));
  for (layout::TriangleInfo& i : b.info) i.ids.y = 0u;  // ids.x, the material, stays per triangle
}

}  // namespace rayspace
