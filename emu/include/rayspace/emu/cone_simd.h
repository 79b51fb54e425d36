// The cone-sphere test on many spheres or many nodes at once, bit for bit the scalar cone::Test on
// each (emu/src/simd/): what the fused traversal runs. One node against a run of spheres (the top
// level: a node against a batch's triangle spheres), or a run of nodes against one sphere (a lower
// level: a pair's children against its triangle). Eight lanes with AVX2, sixteen with AVX-512F,
// chosen at run time; the scalar loop elsewhere.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rayspace/layout.h"
#include "rayspace/settings.h"

namespace rayspace::emu::cone {

using Isa = rayspace::Isa;  // rayspace/settings.h
Isa BestIsa();  // the widest this CPU runs
bool Runs(Isa isa);
const char* IsaName(Isa isa);

// Padding after each array, so that a lane group may read past the last entry.
inline constexpr std::size_t kLanePad = 16;

// Spheres (x, y, z, r), one array per component.
struct SphereArrays {
  std::vector<float> x, y, z, r;
  std::span<const glm::vec4> spheres;  // as given (the caller keeps them), for the scalar loop
};
SphereArrays ToArrays(std::span<const glm::vec4> spheres);

// Cone nodes, one array per field the test reads.
struct NodeArrays {
  std::vector<float> x, y, z, r, ax, ay, az, cosa, sina;
  std::span<const layout::ConeNode> nodes;  // as given (the caller keeps them), for the scalar loop
};
NodeArrays ToArrays(std::span<const layout::ConeNode> nodes);

// Item i that passes writes first + (i << shift) (mod 2^32), in item order, to out, which has room
// for the call's items plus kLanePad. Both return how many were written.
// Node n against spheres [i0, i1) of s.
std::size_t TestSpheres(Isa isa, const layout::ConeNode& n, const SphereArrays& s, std::uint32_t i0, std::uint32_t i1, float eps,
                        std::uint32_t first, int shift, std::uint32_t* out);
// Nodes [k0, k1) of nodes against one sphere.
std::size_t TestNodes(Isa isa, const NodeArrays& nodes, glm::vec4 sphere, std::uint32_t k0, std::uint32_t k1, float eps,
                      std::uint32_t first, int shift, std::uint32_t* out);

// A lower level's pairs (call::TraverseLevel): pair = (parent - base_up) << kPairTriangleBits |
// triangle; the parent's children [first[parent], first[parent + 1]) of `nodes` are tested against
// the triangle's sphere (spheres[triangle], batch-local), and a child k that passes writes
// ((k - base) << kPairTriangleBits) | triangle.
struct PairLevel {
  std::span<const std::uint32_t> pairs, first;
  std::uint32_t base_up, base;
  const glm::vec4* spheres;
};
// Pairs [p0, p1) in order; out has room for their children plus kLanePad. Returns how many were
// written and adds the tests run to tested.
std::size_t TestPairs(Isa isa, const NodeArrays& nodes, const PairLevel& lv, std::size_t p0, std::size_t p1, float eps,
                      std::uint32_t* out, std::uint64_t& tested);

}  // namespace rayspace::emu::cone
