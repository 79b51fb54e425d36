// A node and a ray -> the pipeline's grown node (eqs. 3.8-3.11 and 3.14-3.15, then its float check
// and margins); it must contain the old node and the ray exactly.
#include <string>

#include "input.h"
#include "rayspace/refs/exact_cone.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rayspace;
  fuzz::Reader in(data, size);
  layout::ConeNode node;
  glm::vec3 o, d;
  if (!fuzz::ReadNode(in, node) || !fuzz::ReadRay(in, o, d)) return 0;
  const glm::vec3 r = fuzz::UnitDirection(d);  // leaves are built from unit directions
  const layout::ConeNode grown = emu::cone::GrowNode(node, o, r);
  auto report = [&](const std::string& what) {
    fuzz::PrintNode("node", node);
    std::fprintf(stderr, "ray: (%a, %a, %a) -> (%a, %a, %a)\n", o.x, o.y, o.z, r.x, r.y, r.z);
    fuzz::PrintNode("grown", grown);
    fuzz::Finding(("cone_grow: " + what).c_str());
  };
  if (fuzz::HasNan(grown)) report("NaN in the grown node");
  std::string why;
  if (!refs::ExactNodeContains(grown, node, &why)) report("the grown node does not contain the old node (" + why + ")");
  if (!refs::ExactNodeContainsRay(grown, o, r, &why)) report("the grown node does not contain the ray (" + why + ")");
  return 0;
}
