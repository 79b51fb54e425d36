// Two nodes -> the pipeline's parent node (union, eqs. 3.12-3.15, then its float check and margins);
// the parent must contain both children exactly.
#include <string>

#include "input.h"
#include "rayspace/refs/exact_cone.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rayspace;
  fuzz::Reader in(data, size);
  layout::ConeNode children[2];
  if (!fuzz::ReadNode(in, children[0]) || !fuzz::ReadNode(in, children[1])) return 0;
  const layout::ConeNode parent = emu::cone::ParentNode(children, 2);
  if (fuzz::HasNan(parent)) {
    fuzz::PrintNode("a", children[0]), fuzz::PrintNode("b", children[1]), fuzz::PrintNode("parent", parent);
    fuzz::Finding("cone_union: NaN in the parent node");
  }
  for (const layout::ConeNode& c : children) {
    std::string why;
    if (!refs::ExactNodeContains(parent, c, &why)) {
      fuzz::PrintNode("a", children[0]), fuzz::PrintNode("b", children[1]), fuzz::PrintNode("parent", parent);
      fuzz::Finding(("cone_union: the parent does not contain a child (" + why + ")").c_str());
    }
  }
  return 0;
}
