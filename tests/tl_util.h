// What the traversal-list tests share: a random triangle soup, brute force's closest hit and the
// message of a refused call.
#pragma once
#include <algorithm>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "rayspace/contract.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/error.h"
#include "test_util.h"

namespace rayspace::test {

// n triangles in [-1, 1]^3: every `every`-th of size `big` (kept high in the tree as big triangles),
// the rest of size `small`.
inline std::vector<layout::Triangle> TlSoup(std::uint32_t n, std::uint32_t seed, std::uint32_t every = 10, float big = 0.6f,
                                            float small = 0.06f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<layout::Triangle> t;
  for (std::uint32_t i = 0; i < n; ++i) {
    const glm::vec3 c(u(rng), u(rng), u(rng));
    const float s = i % every == 0 ? big : small;
    t.push_back(MakeTriangle(c + s * glm::vec3(u(rng), u(rng), u(rng)), c + s * glm::vec3(u(rng), u(rng), u(rng)),
                             c + s * glm::vec3(u(rng), u(rng), u(rng))));
  }
  return t;
}

// Every triangle, as the direct tracer's exhaustive mode tests them, ignoring ray.info.y: the packed
// closest hit (nearest t, ties to the lower id) or kMissPacked.
inline std::uint64_t BruteClosest(const std::vector<layout::Triangle>& tris, const layout::Ray& ray) {
  const glm::vec3 o = emu::Xyz(ray.origin_tmin), d = emu::Xyz(ray.direction_tmax);
  const emu::WatertightRay wr = emu::SetupWatertight(o, d);
  std::uint64_t best = emu::kMissPacked;
  for (std::uint32_t i = 0; i < tris.size(); ++i) {
    float t;
    if (i != ray.info.y && emu::IntersectWatertight(wr, emu::Xyz(tris[i].v0), emu::Xyz(tris[i].v1), emu::Xyz(tris[i].v2),
                                                    ray.origin_tmin.w, ray.direction_tmax.w, t))
      best = std::min(best, emu::PackHit(t, i));
  }
  return best;
}

// What `f` throws as InputError, or "" when it throws nothing.
inline std::string InputErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace rayspace::test
