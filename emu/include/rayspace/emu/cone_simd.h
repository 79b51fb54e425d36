// The cone-sphere test on eight spheres at once (emu/src/cone_simd.cpp), bit for bit the scalar
// cone::Test on each: what the fused top level runs where the CPU has AVX2.
#pragma once
#include <cstdint>

#include "rayspace/layout.h"

namespace rayspace::emu::cone {

// Eight spheres, one array per component (lanes past the last sphere hold any finite value).
struct SphereLanes {
  alignas(32) float x[8], y[8], z[8], r[8];
};

bool HaveSimdTest();  // the CPU runs AVX2
// Bit i set when cone::Test(n, sphere i, eps).
std::uint32_t TestEight(const layout::ConeNode& n, const SphereLanes& s, float eps);

}  // namespace rayspace::emu::cone
