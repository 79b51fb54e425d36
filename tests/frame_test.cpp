// Which batches a frame runs follows from the scene; skipped passes carry their reason.
#include <doctest/doctest.h>

#include <algorithm>

#include "rayspace/emu/frame.h"
#include "test_util.h"

using namespace rayspace;

namespace {

emu::FrameResult Render(const Scene& s, int w, int h) {
  const SceneBuffers b = FlattenScene(s);
  auto tracer = emu::MakeDirectTracer(b, emu::DirectMode::kAuto);
  emu::FrameOptions fo;
  fo.width = w;
  fo.height = h;
  return emu::RenderFrame(s, b, *tracer, fo);
}

const emu::PassRecord* Find(const emu::FrameResult& r, const std::string& name) {
  for (const auto& p : r.passes)
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace

TEST_CASE("frame: cornell-mirrors runs shadows and two reflection bounces and draws a picture") {
  const emu::FrameResult r = Render(test::LoadBundled("cornell-mirrors.json"), 48, 48);
  for (int b = 0; b <= 2; ++b) CHECK(r.rays[layout::kRayShadow][b] > 0);
  CHECK(r.rays[layout::kRayReflection][1] > 0);
  CHECK(r.rays[layout::kRayReflection][2] > 0);
  CHECK(r.rays[layout::kRayRefraction][1] == 0);
  const emu::PassRecord* refr = Find(r, "trace.refraction.b1");
  REQUIRE(refr != nullptr);
  CHECK_FALSE(refr->ran);
  CHECK(refr->reason.find("transparency") != std::string::npos);
  // Not blank: a range of grey levels in every channel.
  for (int c = 0; c < 3; ++c) {
    std::uint8_t lo = 255, hi = 0;
    for (std::size_t i = c; i < r.rgb.size(); i += 3) {
      lo = std::min(lo, r.rgb[i]);
      hi = std::max(hi, r.rgb[i]);
    }
    CHECK(hi - lo > 60);
  }
}

TEST_CASE("frame: no lights means no shadow passes and a black image") {
  Scene s = test::LoadBundled("cornell-mirrors.json");
  s.lights.clear();
  const emu::FrameResult r = Render(s, 16, 16);
  const emu::PassRecord* p = Find(r, "trace.shadow.b0");
  REQUIRE(p != nullptr);
  CHECK_FALSE(p->ran);
  CHECK(p->reason == "the scene has no lights");
  CHECK(std::all_of(r.rgb.begin(), r.rgb.end(), [](std::uint8_t v) { return v == 0; }));
  CHECK(r.rays[layout::kRayReflection][1] > 0);  // mirrors still reflect
}

TEST_CASE("frame: no mirrors means no reflection passes, whatever max_depth says") {
  Scene s = test::LoadBundled("cornell-mirrors.json");
  for (MaterialDesc& m : s.materials) m.reflectivity = 0;
  const emu::FrameResult r = Render(s, 16, 16);
  CHECK(r.rays[layout::kRayShadow].size() == 1);  // bounce 0 only
  const emu::PassRecord* p = Find(r, "trace.reflection");
  REQUIRE(p != nullptr);
  CHECK_FALSE(p->ran);
  CHECK(p->reason.find("reflectivity") != std::string::npos);
  CHECK(Find(r, "trace.reflection.b1") == nullptr);
}

TEST_CASE("frame: transparency turns on refraction and max_depth 0 turns bounces off") {
  Scene s = test::LoadBundled("cornell-mirrors.json");
  for (MaterialDesc& m : s.materials)
    if (m.reflectivity == 0) {
      m.transparency = 0.8f;
      m.ior = 1.5f;
    }
  const emu::FrameResult r = Render(s, 32, 32);
  CHECK(r.rays[layout::kRayRefraction][1] > 0);
  s.max_depth = 0;
  const emu::FrameResult z = Render(s, 16, 16);
  const emu::PassRecord* p = Find(z, "trace.reflection");
  REQUIRE(p != nullptr);
  CHECK(p->reason == "max_depth is 0");
  CHECK(z.rays[layout::kRayReflection].size() == 1);
}

TEST_CASE("frame: shadow rays reaching the light, counted against known answers (an open floor, a roofed one)") {
  // A floor at y = 0 seen from above; the point light at y = 5. Every covered pixel's shadow ray is
  // unoccluded; a roof at y = 2, wider than the floor and above the eye's view, occludes every one.
  Scene s;
  s.camera.eye = {0, 1.5f, 2};
  s.camera.target = {0, 0, 0};
  s.materials.push_back(test::Diffuse("m", glm::vec3(0.5f)));
  LightDesc light;
  light.position = {0, 5, 0};
  s.lights = {light};
  test::AddQuad(s, "floor", {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, {-4, 0, -4});
  const emu::FrameResult open = Render(s, 16, 16);
  REQUIRE(open.rays[layout::kRayShadow].size() == 1);
  CHECK(open.rays[layout::kRayShadow][0] > 100);
  REQUIRE(open.unoccluded_shadow_rays.size() == 1);
  CHECK(open.unoccluded_shadow_rays[0] == open.rays[layout::kRayShadow][0]);
  test::AddQuad(s, "roof", {-40, 2, -40}, {40, 2, -40}, {40, 2, 40}, {-40, 2, 40});
  const emu::FrameResult roofed = Render(s, 16, 16);
  CHECK(roofed.rays[layout::kRayShadow][0] == open.rays[layout::kRayShadow][0]);
  REQUIRE(roofed.unoccluded_shadow_rays.size() == 1);
  CHECK(roofed.unoccluded_shadow_rays[0] == 0);
}
