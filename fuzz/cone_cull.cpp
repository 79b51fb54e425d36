// A node, an eps and up to 32 spheres -> the fused top level's group rejects (emu/cone_cull.h), the
// emulator's in double and the kernel's in float (DeviceGroupMisses): where either culls the group,
// the float cone test must reject every sphere of it. Besides the group as given, the group is slid
// along the line from the apex through its first sphere to the nearest position the bound still
// culls (bisection), where the bound is tightest.
#include <optional>
#include <vector>

#include "input.h"
#include "rayspace/emu/cone_cull.h"

namespace {

using rayspace::layout::ConeNode;
namespace cone = rayspace::emu::cone;

bool Culls(bool device, const ConeNode& node, float eps, const std::vector<glm::vec4>& spheres) {
  if (!device) return cone::GroupMisses(cone::CullNodeOf(node, eps), cone::GroupsOf(spheres, cone::kCullGroup), 0);
  const std::optional<glm::vec4> g = cone::DeviceGroupOf(spheres);
  return g && cone::DeviceGroupMisses(node, *g, eps);
}

void Check(bool device, const ConeNode& node, float eps, const std::vector<glm::vec4>& spheres, const char* where) {
  if (!Culls(device, node, eps, spheres)) return;
  for (const glm::vec4& s : spheres) {
    if (!cone::Test(node, s, eps)) continue;
    rayspace::fuzz::PrintNode("node", node);
    std::fprintf(stderr, "eps %a, %s, %s bound; sphere (%a, %a, %a; %a)\n", eps, where, device ? "device" : "host", s.x, s.y,
                 s.z, s.w);
    rayspace::fuzz::Finding("cone_cull: a culled group holds a sphere the cone test keeps");
  }
}

std::vector<glm::vec4> Shifted(const std::vector<glm::vec4>& spheres, glm::dvec3 by) {
  std::vector<glm::vec4> out;
  for (const glm::vec4& s : spheres)
    out.push_back(glm::vec4(float(s.x + by.x), float(s.y + by.y), float(s.z + by.z), s.w));
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rayspace;
  fuzz::Reader in(data, size);
  layout::ConeNode node;
  float eps = 0.0f;
  if (!fuzz::ReadNode(in, node) || !in.Float(eps) || !std::isfinite(eps) || std::fabs(eps) > fuzz::kDomain) return 0;
  std::vector<glm::vec4> spheres;
  glm::vec4 s;
  while (spheres.size() < cone::kCullGroup && fuzz::ReadSphere(in, s)) spheres.push_back(s);
  if (spheres.empty()) return 0;
  for (const bool device : {false, true}) {
    Check(device, node, eps, spheres, "as given");
    // Slide: the group moved by t (first sphere - apex), t in [-1, 64], to the edge of culling.
    const glm::dvec3 dir = glm::dvec3(spheres[0]) - glm::dvec3(node.sphere);
    double lo = -1.0, hi = 64.0;
    auto culled = [&](double t) { return Culls(device, node, eps, Shifted(spheres, dir * t)); };
    if (culled(lo) || !culled(hi)) continue;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (culled(mid) ? hi : lo) = mid;
    }
    Check(device, node, eps, Shifted(spheres, dir * hi), "at the edge of culling");
  }
  return 0;
}
