// The interface of the multi-lane watertight ray-triangle test (intersect_lanes.inl, compiled in
// lanes_avx2.cpp and lanes_avx512.cpp): plain floats and pointers only, for the reason cone_lanes.h
// gives.
#pragma once
#include <cstdint>

namespace rayspace::emu::intersect_lanes {

// Rays set up for the watertight test (emu::WatertightRay), one array per field, each readable 16
// entries past its last.
struct RayArrays {
  const float *ox, *oy, *oz, *dx, *dy, *dz, *sx, *sy, *tmin, *tmax;
  const std::int32_t *kx, *ky, *kz;
};
// A triangle: vertices and its scaled plane normal (emu::PlaneNormalOf).
struct Triangle {
  float v0[3], v1[3], v2[3], n[3];
};

// Rays [j, j + 8) (AVX2) or [j, j + 16) (AVX-512F) against tri: bit i set when ray j + i hits with
// tmin < t < tmax; t[i] its distance.
std::uint32_t RaysAvx2(const RayArrays& r, const Triangle& tri, std::uint32_t j, float* t);
std::uint32_t RaysAvx512(const RayArrays& r, const Triangle& tri, std::uint32_t j, float* t);

// The other way round: one ray (set up for the watertight test) against sixteen triangles, one array
// per field (vertices, then the scaled plane normal), for grid.trace's cell lists.
struct OneRay {
  float org[3], dir[3], sx, sy, tmin, tmax;
  std::int32_t kx, ky, kz;
};
struct TriangleLanes {
  float v[12][16];  // v0.xyz, v1.xyz, v2.xyz, n.xyz; lane i in column i
};
// The ray against lanes [0, 8) (AVX2) or [0, 16) (AVX-512F) of tris: bit i set when the ray hits
// triangle i with tmin < t < tmax; t[i] its distance.
std::uint32_t TrianglesAvx2(const OneRay& r, const TriangleLanes& tris, float* t);
std::uint32_t TrianglesAvx512(const OneRay& r, const TriangleLanes& tris, float* t);

}  // namespace rayspace::emu::intersect_lanes
