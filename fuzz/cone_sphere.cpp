// A node and a sphere -> the kernel's cone-sphere test; it must never say "miss" when the exact
// answer is "hit" (scene margin eps = 0: the test alone must be conservative).
#include "input.h"
#include "rayspace/refs/exact_cone.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rayspace;
  fuzz::Reader in(data, size);
  layout::ConeNode node;
  glm::vec4 sphere;
  if (!fuzz::ReadNode(in, node) || !fuzz::ReadSphere(in, sphere)) return 0;
  if (!emu::cone::Test(node, sphere, 0.0f) && refs::ExactNodeMeetsSphere(node, sphere)) {
    fuzz::PrintNode("node", node);
    std::fprintf(stderr, "sphere: (%a, %a, %a; %a)\n", sphere.x, sphere.y, sphere.z, sphere.w);
    fuzz::Finding("cone_sphere: the test misses a sphere the exact decision hits");
  }
  return 0;
}
