// The relaxed model of the raster's fragment stage (verify/src/spec_raster.cpp): where both sides
// cover a pixel with the same triangle, depth, position and normal may be any value of the stage's
// arithmetic under Vulkan's precision; the copied words may not change.
#include <doctest/doctest.h>

#include <cmath>
#include <algorithm>
#include <array>
#include <functional>

#include "rayspace/emu/passes.h"
#include "rayspace/emu/raster_detail.h"
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

namespace {

// Two big triangles each covering the whole view, B at depth `z_b` (A at 0). The device's G-buffer
// is the emulator's with a 3 x 3 block about pixel (4, 3) given to the triangle the emulator did
// not pick there, each word that triangle's fragment.
struct OverlapCase {
  Scene scene;
  SceneBuffers buffers;
  emu::call::Raster call;
  explicit OverlapCase(float z_b) {
    scene.camera.eye = {0, 0, 1};
    scene.camera.target = {0.2f, 0.1f, 0};
    scene.camera.up = {0, 1, 0};
    scene.camera.fov_y_deg = 60;
    scene.materials.push_back(test::Diffuse("wall", glm::vec3(0.5f)));
    for (const auto& [a, b, c] : {std::array<glm::vec3, 3>{glm::vec3(-100, -100, 0), glm::vec3(100, -100, 0), glm::vec3(0, 100, 0)},
                                  std::array<glm::vec3, 3>{glm::vec3(-90, -110, z_b), glm::vec3(110, -90, z_b), glm::vec3(10, 120, z_b)}}) {
      Object o;
      o.name = "wall";
      o.positions = {a, b, c};
      o.normals.assign(3, glm::vec3(0, 0, 1));
      o.material.assign(1, 0);
      scene.objects.push_back(o);
    }
    buffers = FlattenScene(scene);
    call = {.frame = MakeFrameConstants(scene, buffers, 8, 6), .scene = &buffers};
  }
  verify::SpecVerdict Verdict() const {
    const emu::GBuffer emulated = emu::PassRaster(call);
    emu::GBuffer device = emulated;
    for (int y = 2; y <= 4; ++y)
      for (int x = 3; x <= 5; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * 8 + x;
        const std::uint32_t other = emulated.prim[i] == 0 ? 1u : 0u;
        const emu::raster::Fragment f = emu::raster::ShadeFragment(call.frame, buffers, other, x, y);
        device.prim[i] = other;
        device.depth[i] = f.depth;
        device.position[i] = glm::vec4(f.position, 1.0f);
        device.normal[i] = glm::vec4(emu::ShadingNormal(buffers, other, f.position), emulated.normal[i].w);
      }
    return verify::ClassifyWithinSpec("raster.flips", verify::EncodeCall(call), verify::EncodeOutputs(call, &emulated),
                                      verify::EncodeOutputs(call, &device));
  }
};

}  // namespace

TEST_CASE("relaxed model: inside two nearly coplanar triangles the depth test may pick either, not one surely behind") {
  // 2e-7 behind: within the depths' rounding, yet the emulator picks A at every pixel, so a device
  // picking B in a block is away from every edge of its image.
  const OverlapCase close(-2e-7f);
  const emu::GBuffer g = emu::PassRaster(close.call);
  REQUIRE(std::count(g.prim.begin(), g.prim.end(), 0u) == 48);
  const verify::SpecVerdict flip = close.Verdict();
  CHECK(flip.modelled);
  CHECK(flip.within == 1);  // the block's centre: its neighbours are the block, so not an edge
  CHECK(flip.beyond == 0);
  const verify::SpecVerdict behind = OverlapCase(-1e-6f).Verdict();  // a few ULP of depth apart: never
  CHECK(behind.beyond == 1);
  CHECK(behind.first_beyond.find("behind") != std::string::npos);
}
