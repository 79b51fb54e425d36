// The rounded arithmetic of a perspective cell's walk (grid.trace, gpu/shaders/grid_trace.comp),
// templated over the scalar like the other kernel math (rayspace/emu/intersect.h): float is the
// emulator's and the kernel's arithmetic, operation for operation; verify::SpecReal asks what a
// conformant device may compute instead (docs/numerics.md, "The relaxed device model").
#pragma once
#include <cstdint>

#include "rayspace/emu/intersect.h"

namespace rayspace::emu::grid {

// The face (0..5: +x, -x, +y, -y, +z, -z) and the (u, v) in [-1, 1] of a direction seen from a light;
// u, v are the direction's two other components over the major one. The face is a comparison of the
// direction's magnitudes (exact on every device); u and v are quotients.
template <typename S>
struct FaceUvOf {
  std::uint32_t face = 0;
  S u{0.0f}, v{0.0f};
};

template <typename S>
FaceUvOf<S> DirectionFaceOf(glm::vec3 d) {
  const glm::vec3 a(Abs(d.x), Abs(d.y), Abs(d.z));
  const std::uint32_t major = a.x >= a.y && a.x >= a.z ? 0u : (a.y >= a.z ? 1u : 2u);
  const S m(a[major]);
  FaceUvOf<S> f;
  f.face = 2u * major + (d[major] < 0.0f ? 1u : 0u);
  f.u = S(d[(major + 1) % 3]) / m;
  f.v = S(d[(major + 2) % 3]) / m;
  return f;
}

// The cell coordinate along one side of a face of n cells: (c + 1) n / 2 (FaceCell truncates it).
template <typename S>
S FaceCoordinateOf(S c, std::uint32_t n) {
  const S half = S(static_cast<float>(n)) * S(0.5f);
  return (c + S(1.0f)) * half;
}

// Whether the triangle faces away from the point o: dot(n, o - v0) < 0, n as the watertight test's.
template <typename S>
bool FacesAwayOf(Vec3<S> v0, Vec3<S> v1, Vec3<S> v2, Vec3<S> o) {
  const Vec3<S> n = PlaneNormalOf(v0, v1, v2);
  return Dot(n, o - v0) < S(0.0f);
}

}  // namespace rayspace::emu::grid
