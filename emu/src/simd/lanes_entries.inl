// The entry points of one instruction set's unit (cone_lanes.h, intersect_lanes.h), named by the
// including unit's RS_ISA(Name) (NameAvx2, NameAvx512), after its lane type and the tests, outside
// any namespace.

namespace rayspace::emu::cone::lanes {

std::size_t RS_ISA(Spheres)(const Node& n, const SphereArrays& s, std::uint32_t i0, std::uint32_t i1, float eps, const Output& o) {
  return SpheresRun(n, s, i0, i1, eps, o);
}

std::size_t RS_ISA(Nodes)(const NodeArrays& n, const float sphere[4], std::uint32_t k0, std::uint32_t k1, float eps, const Output& o) {
  return NodesRun(n, sphere, k0, k1, eps, o);
}

std::size_t RS_ISA(Pairs)(const NodeArrays& n, const PairLevel& lv, std::size_t p0, std::size_t p1, float eps, std::uint32_t* out,
                          std::uint64_t* tested) {
  return PairsRun(n, lv, p0, p1, eps, out, tested);
}

}  // namespace rayspace::emu::cone::lanes

namespace rayspace::emu::intersect_lanes {

std::uint32_t RS_ISA(Rays)(const RayArrays& r, const Triangle& tri, std::uint32_t j, float* t) { return cone::lanes::RaysLanes(r, tri, j, t); }

std::uint32_t RS_ISA(Triangles)(const OneRay& r, const TriangleLanes& tris, float* t) { return cone::lanes::TrianglesLanes(r, tris, t); }

}  // namespace rayspace::emu::intersect_lanes
