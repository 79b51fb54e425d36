// The tracers the hard cases hold to one answer: the exhaustive direct tracer, the hierarchy (CRSH)
// with flat objects and with the object tree's joint descent, and (with_embree) the Embree oracle.
#pragma once
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/tracer.h"
#include "rayspace/refs/embree_tracer.h"
#include "test_util.h"

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

// A scene of single triangles, each its own object, with one material.
inline void AddTriangle(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  Object o;
  o.name = fmt::format("t{}", s.objects.size());
  o.positions = {a, b, c};
  o.normals.assign(3, glm::normalize(glm::cross(b - a, c - a)));
  o.material.assign(1, 0);
  s.objects.push_back(o);
}

inline Scene OneScene() {
  Scene s;
  s.materials.push_back(test::Diffuse("m", glm::vec3(0.5f)));
  return s;
}

inline layout::Ray Ray(glm::vec3 o, glm::vec3 d, float tmin, float tmax, std::uint32_t kind = layout::kRayReflection) {
  layout::Ray r{};
  r.origin_tmin = glm::vec4(o, tmin);
  r.direction_tmax = glm::vec4(d, tmax);
  r.info = glm::uvec4(0, layout::kNoPrim, kind, 0);
  return r;
}

// The embree path computes t its own way (not bit for bit the watertight test's); the convention
// holds for the t each path computes, so its t is compared within a few ulps only.
inline bool SameT(float a, float b, bool exact) { return exact ? a == b : std::fabs(a - b) <= 8.0f * std::fabs(b) * 0x1p-24f; }

// Every tracer's closest hit for each ray, and its occlusion flag for the same rays as shadow rays.
// with_embree false: the emulator's tracers only (where Embree's own t may order exact ties otherwise).
inline void ExpectEveryTracer(const SceneBuffers& buf, const std::vector<layout::Ray>& rays, const std::vector<std::uint64_t>& expected,
                              bool with_embree = true) {
  HardTracers tracers(buf, with_embree);
  std::vector<layout::Ray> shadow = rays;
  for (layout::Ray& r : shadow) r.info.z = layout::kRayShadow;
  for (std::size_t k = 0; k < tracers.all.size(); ++k) {
    CAPTURE(tracers.names[k]);
    std::vector<std::uint64_t> hits;
    std::vector<std::uint32_t> occluded;
    tracers.all[k]->Closest(rays, hits);
    tracers.all[k]->Occluded(shadow, occluded);
    REQUIRE(hits.size() == rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
      CAPTURE(i);
      CHECK(emu::HitPrim(hits[i]) == emu::HitPrim(expected[i]));
      if (expected[i] != emu::kMissPacked && hits[i] != emu::kMissPacked)
        CHECK(SameT(emu::HitT(hits[i]), emu::HitT(expected[i]), tracers.names[k] != "embree"));
      CHECK(occluded[i] == (expected[i] != emu::kMissPacked ? 1u : 0u));
    }
  }
}

}  // namespace rayspace::test
