// The interface between the dispatching code (emu/src/cone_simd.cpp) and the translation units
// compiled for one instruction set each (lanes_avx2.cpp, lanes_avx512.cpp). Plain
// floats and pointers only: those units are built with -mavx2 or -mavx512f, and any inline
// function they shared with the rest of the program (a std:: or glm template) could be linked into
// code that runs on a CPU without those instructions.
#pragma once
#include <cstddef>
#include <cstdint>

namespace rayspace::emu::cone::lanes {

// A cone node's fields (layout::ConeNode: sphere, cone axis and cosine, sine).
struct Node {
  float x, y, z, r, ax, ay, az, cosa, sina;
};
// Nine arrays of nodes or four of spheres, one per field, each readable 16 entries past its last.
struct NodeArrays {
  const float *x, *y, *z, *r, *ax, *ay, *az, *cosa, *sina;
};
struct SphereArrays {
  const float *x, *y, *z, *r;
};
// Where the survivors go: item i writes first + (i << shift) (mod 2^32) to out, in item order; out
// has room for the items of the call plus 16.
struct Output {
  std::uint32_t first;
  int shift;
  std::uint32_t* out;
};

// A lower level's pairs: pair = (parent - base_up) << bits | triangle; the parent's children
// [first[parent], first[parent + 1]) are tested against the triangle's sphere (spheres4: x, y, z, r
// per batch-local triangle), and child k, when it passes, writes ((k - base) << bits) | triangle.
struct PairLevel {
  const std::uint32_t* pairs;
  const std::uint32_t* first;
  std::uint32_t base_up, base;
  const float* spheres4;
  int bits;
};

// Node n against spheres [i0, i1); returns the number written.
std::size_t SpheresAvx2(const Node& n, const SphereArrays& s, std::uint32_t i0, std::uint32_t i1, float eps, const Output& o);
std::size_t SpheresAvx512(const Node& n, const SphereArrays& s, std::uint32_t i0, std::uint32_t i1, float eps, const Output& o);
// Nodes [k0, k1) against sphere (x, y, z, r).
std::size_t NodesAvx2(const NodeArrays& n, const float sphere[4], std::uint32_t k0, std::uint32_t k1, float eps, const Output& o);
std::size_t NodesAvx512(const NodeArrays& n, const float sphere[4], std::uint32_t k0, std::uint32_t k1, float eps, const Output& o);

// Pairs [p0, p1) of a level, in order; out has room for their children plus 16. Returns the number
// written and adds the tests run to *tested.
std::size_t PairsAvx2(const NodeArrays& n, const PairLevel& lv, std::size_t p0, std::size_t p1, float eps, std::uint32_t* out,
                      std::uint64_t* tested);
std::size_t PairsAvx512(const NodeArrays& n, const PairLevel& lv, std::size_t p0, std::size_t p1, float eps, std::uint32_t* out,
                        std::uint64_t* tested);

}  // namespace rayspace::emu::cone::lanes
