// The tracers the hard cases hold to one answer: the exhaustive direct tracer, the hierarchy (CRSH)
// with flat objects and with the object tree's joint descent, and (with_embree) the Embree oracle.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/tracer.h"
#include "rayspace/refs/embree_tracer.h"

namespace rayspace::test {

struct HardTracers {
  std::vector<glm::vec4> tri_spheres, obj_spheres;
  std::vector<std::unique_ptr<Tracer>> all;
  std::vector<std::string> names;
  explicit HardTracers(const SceneBuffers& buf, bool with_embree = false)
      : tri_spheres(emu::PassTriangleSpheres(buf.triangles)), obj_spheres(emu::PassObjectSpheres(buf)) {
    all.push_back(emu::MakeDirectTracer(buf, emu::DirectMode::kExhaustive));
    names.push_back("direct");
    for (const bool tree : {false, true}) {
      emu::HierarchyConfig cfg;
      cfg.object_tree = tree;
      cfg.subdivision = 4;
      all.push_back(emu::MakeHierarchyTracer(buf, cfg));
      names.push_back(tree ? "crsh, object tree" : "crsh, flat");
    }
    if (with_embree) {
      all.push_back(refs::MakeEmbreeTracer(buf, 1));
      names.push_back("embree");
    }
    for (auto& t : all) t->Prepare(tri_spheres, obj_spheres);
  }
};

}  // namespace rayspace::test
