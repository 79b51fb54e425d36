// A ray and a triangle -> the kernels' watertight test; it must not miss a hit that the exact test
// finds robustly inside the triangle: farther than 2^-16 of the coordinates' magnitude from every
// edge and from the origin (closer hits depend on the rounding of the translation to the origin,
// which no float test avoids; hits exactly on an edge are a convention).
#include "input.h"
#include "rayspace/refs/exact.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rayspace;
  fuzz::Reader in(data, size);
  glm::vec3 o, d;
  float v[9];
  if (!fuzz::ReadRay(in, o, d) || !in.Floats(v, 9) || !fuzz::Finite(v, 9)) return 0;
  d = fuzz::UnitDirection(d);  // ray generation hands the kernels unit directions
  layout::Triangle t{};
  t.v0 = glm::vec4(v[0], v[1], v[2], 0.0f);
  t.v1 = glm::vec4(v[3], v[4], v[5], 0.0f);
  t.v2 = glm::vec4(v[6], v[7], v[8], 0.0f);
  layout::Ray r{};
  r.origin_tmin = glm::vec4(o, 0.0f);
  r.direction_tmax = glm::vec4(d, INFINITY);
  float th;
  const bool hit = emu::IntersectWatertight(emu::SetupWatertight(o, d), emu::Xyz(t.v0), emu::Xyz(t.v1), emu::Xyz(t.v2), 0.0f,
                                            INFINITY, th);
  if (!hit && refs::ExactRobustInteriorHit(o, d, emu::Xyz(t.v0), emu::Xyz(t.v1), emu::Xyz(t.v2), 0x1p-16f)) {
    std::fprintf(stderr, "ray (%a, %a, %a) -> (%a, %a, %a)\n", o.x, o.y, o.z, d.x, d.y, d.z);
    std::fprintf(stderr, "triangle (%a, %a, %a) (%a, %a, %a) (%a, %a, %a)\n", v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8]);
    fuzz::Finding("ray_triangle: the watertight test misses a robust interior hit");
  }
  return 0;
}
