#version 460
// tree.expand: per pair the number of its candidates; mirrors emu PassTreeExpand.
// Fault 1: own triangles not counted. Fault 2: a cone node's last child not counted. Fault 3: the
// object side refined wherever the item is a node.
#include "common.glsl"
#include "cone.glsl"
#define TREE_FAULT_NO_OWN_TRIS (kFault == 1u)
#define TREE_FAULT_NO_LAST_CONE_CHILD (kFault == 2u)
#define TREE_FAULT_NO_SPLIT (kFault == 3u)
#include "tree.glsl"

void main() {
  const uint p = GlobalIndex();
  if (p >= pc.count) return;
  flags[p] = CountOf(Expand(pair_cone[p], pair_item[p]));
}
