// The relaxed model of the raster's fragment stage (verify/src/spec_raster.cpp): where both sides
// cover a pixel with the same triangle, depth, position and normal may be any value of the stage's
// arithmetic under Vulkan's precision; the copied words may not change.
#include <doctest/doctest.h>

#include <cmath>
#include <functional>

#include "rayspace/emu/passes.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/spec_model.h"
#include "test_util.h"

namespace {

using namespace rayspace;

// A wall across the whole view (z = 0, seen from z = 1, tilted so depth varies): every pixel covered
// by the same triangle pair on both sides.
struct WallCase {
  Scene scene;
  SceneBuffers buffers;
  emu::call::Raster call;
  WallCase() {
    scene.camera.eye = {0, 0, 1};
    scene.camera.target = {0.2f, 0.1f, 0};
    scene.camera.up = {0, 1, 0};
    scene.camera.fov_y_deg = 60;
    scene.materials.push_back(test::Diffuse("wall", glm::vec3(0.5f)));
    test::AddQuad(scene, "wall", {-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0});
    buffers = FlattenScene(scene);
    call = {.frame = MakeFrameConstants(scene, buffers, 8, 6), .scene = &buffers};
  }
  verify::SpecVerdict Verdict(const std::function<void(emu::GBuffer&)>& plant) const {
    const emu::GBuffer emulated = emu::PassRaster(call);
    emu::GBuffer device = emulated;
    plant(device);
    return verify::ClassifyWithinSpec("raster.fragments", verify::EncodeCall(call), verify::EncodeOutputs(call, &emulated),
                                      verify::EncodeOutputs(call, &device));
  }
};

float Ulps(float x, int n) {
  for (int i = 0; i < n; ++i) x = std::nextafter(x, INFINITY);
  return x;
}

}  // namespace

TEST_CASE("relaxed model: a covered pixel's depth, position and normal within the fragment stage's precision, copies exact") {
  const WallCase w;
  const std::size_t i = 3 * 8 + 4;  // an interior pixel
  REQUIRE(emu::PassRaster(w.call).prim[i] != layout::kNoPrim);
  const verify::SpecVerdict close = w.Verdict([&](emu::GBuffer& g) {
    g.depth[i] = Ulps(g.depth[i], 1);  // tt is a quotient: a ULP is within 2.5
    g.position[i].x = Ulps(g.position[i].x, 1);
    g.normal[i].z = Ulps(g.normal[i].z, 1);
  });
  CHECK(close.modelled);
  CHECK(close.within == 1);
  CHECK(close.beyond == 0);
  CHECK(w.Verdict([&](emu::GBuffer& g) { g.depth[i] *= 1.01f; }).beyond == 1);
  CHECK(w.Verdict([&](emu::GBuffer& g) { g.position[i].y += 0.01f; }).beyond == 1);
  CHECK(w.Verdict([&](emu::GBuffer& g) { g.normal[i].x += 0.01f; }).beyond == 1);
  CHECK(w.Verdict([&](emu::GBuffer& g) { g.diffuse[i].x = Ulps(g.diffuse[i].x, 1); }).beyond == 1);  // a copy
  CHECK(w.Verdict([&](emu::GBuffer& g) { g.normal[i].w = 0.5f; }).beyond == 1);  // the transparency, a copy
}
