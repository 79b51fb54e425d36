// Final ray-triangle tests of the surviving level-1 pairs (watertight test, atomic closest hit or
// occlusion flag). Mirrors gpu/shaders/intersect.comp.
#include <atomic>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

std::vector<std::uint32_t> PassIntersect(const call::Intersect& c) {
  return IntersectWith(
      [](const layout::Ray& r, const layout::Triangle& t, float& th) {
        return IntersectWatertight(SetupWatertight(Xyz(r.origin_tmin), Xyz(r.direction_tmax)), Xyz(t.v0), Xyz(t.v1), Xyz(t.v2),
                                   r.origin_tmin.w, r.direction_tmax.w, th);
      },
      [&](std::uint32_t ray, const layout::Ray&, float th, std::uint32_t prim) { RecordClosestHit(*c.hits, ray, PackHit(th, prim)); },
      c);
}

}  // namespace rayspace::emu
