// Reading fuzzer bytes as the documented float32 records (fuzz/README.md). Inputs that are not valid
// after normalisation are skipped (the harness returns), never turned into a crash.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "rayspace/emu/cone.h"

namespace rayspace::fuzz {

class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  // Little-endian float32 (the host is little-endian; static_assert in the harness build).
  bool Float(float& f) {
    if (size_ < 4) return false;
    std::memcpy(&f, data_, 4);
    data_ += 4;
    size_ -= 4;
    return true;
  }
  bool Floats(float* f, int n) {
    for (int i = 0; i < n; ++i)
      if (!Float(f[i])) return false;
    return true;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
};

// The pipeline's numeric domain: finite, magnitude at most 2^62 (coordinates, radii, directions), so
// that differences stay below 2^63 and their cross products below 2^127 (docs/numerics.md).
inline constexpr float kDomain = 0x1p62f;
inline bool Finite(const float* f, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(f[i]) || std::fabs(f[i]) > kDomain) return false;
  return true;
}

// [centre x, y, z, radius, axis x, y, z, half-angle in radians] -> a node as the pipeline stores it:
// unit axis (normalised in float), (cos, sin) of the half-angle rounded from double, full at >= pi.
inline bool ReadNode(Reader& in, layout::ConeNode& n) {
  float f[8];
  if (!in.Floats(f, 8) || !Finite(f, 8) || f[3] < 0.0f || f[7] < 0.0f) return false;
  // Unit axis: normalised in double, rounded once (as the host would store it).
  const double ax = f[4], ay = f[5], az = f[6], len = std::sqrt(ax * ax + ay * ay + az * az);
  if (!(len > 0.0)) return false;
  n.sphere = glm::vec4(f[0], f[1], f[2], f[3]);
  n.cone = glm::vec4(static_cast<float>(ax / len), static_cast<float>(ay / len), static_cast<float>(az / len), 0.0f);
  if (f[7] >= 3.14159265358979323846) {
    n.cone = glm::vec4(1.0f, 0.0f, 0.0f, -1.0f);
    n.extra = glm::vec4(0.0f, 1.0f, 0.0f, 0.0f);
    return true;
  }
  n.cone.w = static_cast<float>(std::cos(static_cast<double>(f[7])));
  n.extra = glm::vec4(static_cast<float>(std::sin(static_cast<double>(f[7]))), 1.0f, 0.0f, 0.0f);
  return true;
}

// [origin x, y, z, direction x, y, z]; the direction must be nonzero and finite when squared.
inline bool ReadRay(Reader& in, glm::vec3& o, glm::vec3& d) {
  float f[6];
  if (!in.Floats(f, 6) || !Finite(f, 6)) return false;
  o = glm::vec3(f[0], f[1], f[2]);
  d = glm::vec3(f[3], f[4], f[5]);
  return d.x != 0.0f || d.y != 0.0f || d.z != 0.0f;
}

// The pipeline hands kernels unit directions; a raw direction is normalised in double and rounded
// once (a float normalisation of a tiny vector would underflow: outside the domain of ray generation).
inline glm::vec3 UnitDirection(glm::vec3 d) {
  const double l = std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
  return {static_cast<float>(d.x / l), static_cast<float>(d.y / l), static_cast<float>(d.z / l)};
}

// [centre x, y, z, radius]
inline bool ReadSphere(Reader& in, glm::vec4& s) {
  float f[4];
  if (!in.Floats(f, 4) || !Finite(f, 4) || f[3] < 0.0f) return false;
  s = glm::vec4(f[0], f[1], f[2], f[3]);
  return true;
}

inline void PrintNode(const char* name, const layout::ConeNode& n) {
  std::fprintf(stderr, "%s: sphere (%a, %a, %a; %a) axis (%a, %a, %a) cos %a sin %a\n", name, n.sphere.x, n.sphere.y,
               n.sphere.z, n.sphere.w, n.cone.x, n.cone.y, n.cone.z, n.cone.w, n.extra.x);
}

[[noreturn]] inline void Finding(const char* what) {
  std::fprintf(stderr, "FINDING: %s\n", what);
  std::abort();
}

inline bool HasNan(const layout::ConeNode& n) {
  for (int k = 0; k < 4; ++k)
    if (std::isnan(n.sphere[k]) || std::isnan(n.cone[k]) || std::isnan(n.extra[k])) return true;
  return false;
}

}  // namespace rayspace::fuzz
