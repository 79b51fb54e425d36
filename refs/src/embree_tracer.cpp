#include "rayspace/refs/embree_tracer.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rayspace/emu/intersect.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::refs {
namespace {

constexpr const char* kIsa = "sse4.2";

// The context carries the primitive a ray must ignore (the surface it leaves), like the emulator,
// and the closest hit accepted so far, for the tie-break.
struct Context {
  RTCIntersectContext base;
  std::uint32_t ignore;
  float tmin, tmax;
  float best_t;
  std::uint32_t best_prim;
  glm::dvec3 dir;
  const layout::Triangle* one_sided;  // the scene's triangles when one-sided, else null
};

// One-sided triangles (SceneBuffers::one_sided): a candidate met from behind, or along its plane, is
// none. In double, where the edges and the normal of float vertices are all but exact; what it gets
// wrong is a grazing ray, which the exact judge settles.
bool Behind(const Context& ctx, std::uint32_t prim) {
  if (ctx.one_sided == nullptr) return false;
  const layout::Triangle& t = ctx.one_sided[prim];
  const glm::dvec3 v0(emu::Xyz(t.v0));
  const glm::dvec3 n = glm::cross(glm::dvec3(emu::Xyz(t.v1)) - v0, glm::dvec3(emu::Xyz(t.v2)) - v0);
  return !(glm::dot(ctx.dir, n) < 0.0);
}

// tmin < t < tmax on the distance Embree reports (docs/numerics.md, "The hit convention"). Embree's
// own bounds test t >= tnear and t <= tfar on the scaled numerator before it divides, so the ray is
// handed to it with bounds a little wider (Fill) and the convention is applied here.
bool Outside(const Context& ctx, float t) { return !(t > ctx.tmin && t < ctx.tmax); }

// Embree calls the filter with the candidate's distance in the ray's tfar, for candidates no farther
// than the closest accepted one. Equal distances go to the lower primitive id, as the emulator's
// packed (t, id) minimum does (docs/numerics.md, "The hit convention"); Embree alone would keep the
// last one its traversal meets.
void IntersectFilter(const RTCFilterFunctionNArguments* args) {
  auto* ctx = reinterpret_cast<Context*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const std::uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
    const float t = RTCRayN_tfar(args->ray, args->N, i);
    if (prim == ctx->ignore || Outside(*ctx, t) || (t == ctx->best_t && prim > ctx->best_prim) || Behind(*ctx, prim)) {
      args->valid[i] = 0;
      continue;
    }
    ctx->best_t = t;
    ctx->best_prim = prim;
  }
}

void OccludedFilter(const RTCFilterFunctionNArguments* args) {
  const auto* ctx = reinterpret_cast<const Context*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const std::uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
    if (prim == ctx->ignore || Outside(*ctx, RTCRayN_tfar(args->ray, args->N, i)) || Behind(*ctx, prim))
      args->valid[i] = 0;
  }
}

class EmbreeTracer final : public Tracer {
 public:
  EmbreeTracer(const SceneBuffers& scene, int threads) {
    if (scene.one_sided) one_sided_ = scene.triangles;
    const std::string config = fmt::format("isa={},threads={}", kIsa, threads > 0 ? threads : 0);
    device_ = rtcNewDevice(config.c_str());
    if (!device_) throw std::runtime_error(fmt::format("rtcNewDevice(\"{}\") failed: error {}", config, static_cast<int>(rtcGetDeviceError(nullptr))));
    scene_ = rtcNewScene(device_);
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
    const std::size_t n = scene.triangles.size();
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), 3 * n));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), n));
    if (!v || !idx) throw std::runtime_error("rtcSetNewGeometryBuffer failed");
    for (std::size_t t = 0; t < n; ++t) {
      const layout::Triangle& tri = scene.triangles[t];
      const glm::vec4* vs[3] = {&tri.v0, &tri.v1, &tri.v2};
      for (int k = 0; k < 3; ++k) {
        v[9 * t + 3 * k + 0] = vs[k]->x;
        v[9 * t + 3 * k + 1] = vs[k]->y;
        v[9 * t + 3 * k + 2] = vs[k]->z;
        idx[3 * t + k] = static_cast<unsigned>(3 * t + k);
      }
    }
    rtcSetGeometryIntersectFilterFunction(geom, IntersectFilter);
    rtcSetGeometryOccludedFilterFunction(geom, OccludedFilter);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    triangles_ = n;
  }
  ~EmbreeTracer() override {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }

  std::string Name() const override { return "embree"; }
  void Describe(nlohmann::json& out) const override {
    out["name"] = Name();
    out["version"] = fmt::format("{}.{}.{}", rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_VERSION_MAJOR),
                                 rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_VERSION_MINOR),
                                 rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_VERSION_PATCH));
    out["isa"] = kIsa;
    out["build_quality"] = "high";
    out["scene_flags"] = "robust";
    out["triangles"] = one_sided_.empty() ? "two-sided" : "one-sided (a filter drops hits from behind)";
  }

  // The BVH is built before the first batch, timed as the sub-pass "embree.build" as the grids' build
  // is (a frame with nothing to trace builds none); an oracle's first query builds it untimed.
  void BeginBatch(const BatchContext& ctx) override {
    if (committed_) return;
    const auto t0 = std::chrono::steady_clock::now();
    Commit();
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (ctx.subpasses) ctx.subpasses->push_back({"embree.build", ms, triangles_});
  }

  void Closest(const std::vector<layout::Ray>& rays, std::vector<std::uint64_t>& hits) override {
    Commit();
    hits.assign(rays.size(), emu::kMissPacked);
    ParallelFor(rays.size(), [&](std::size_t i) {
      Context ctx;
      Start(rays[i], ctx);
      ctx.best_t = INFINITY;
      ctx.best_prim = layout::kNoPrim;
      RTCRayHit rh{};
      Fill(rays[i], rh.ray);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene_, &ctx.base, &rh);
      if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) hits[i] = emu::PackHit(rh.ray.tfar, rh.hit.primID);
    });
  }

  void Occluded(const std::vector<layout::Ray>& rays, std::vector<std::uint32_t>& occluded) override {
    Commit();
    occluded.assign(rays.size(), 0u);
    ParallelFor(rays.size(), [&](std::size_t i) {
      Context ctx;
      Start(rays[i], ctx);
      RTCRay r{};
      Fill(rays[i], r);
      rtcOccluded1(scene_, &ctx.base, &r);
      occluded[i] = r.tfar == -INFINITY ? 1u : 0u;
    });
  }

 private:
  void Commit() {
    std::call_once(commit_, [&] {
      rtcCommitScene(scene_);
      if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw std::runtime_error("Embree scene build failed");
      committed_ = true;
    });
  }

  void Start(const layout::Ray& in, Context& ctx) const {
    rtcInitIntersectContext(&ctx.base);
    ctx.dir = glm::dvec3(emu::Xyz(in.direction_tmax));
    ctx.one_sided = one_sided_.empty() ? nullptr : one_sided_.data();
    ctx.ignore = in.info.y;
    ctx.tmin = in.origin_tmin.w;
    ctx.tmax = in.direction_tmax.w;
  }

  static void Fill(const layout::Ray& in, RTCRay& r) {
    r.org_x = in.origin_tmin.x;
    r.org_y = in.origin_tmin.y;
    r.org_z = in.origin_tmin.z;
    const float tmin = in.origin_tmin.w;
    r.tnear = tmin > 0.0f ? tmin * (1.0f - 0x1p-16f) : tmin;
    r.dir_x = in.direction_tmax.x;
    r.dir_y = in.direction_tmax.y;
    r.dir_z = in.direction_tmax.z;
    // Wider by 2^-16 (the filters apply the exact bounds to the reported t).
    const float tmax = in.direction_tmax.w;
    r.tfar = tmax > 0.0f ? tmax * (1.0f + 0x1p-16f) : tmax;
    r.mask = ~0u;
    r.flags = 0;
    r.time = 0;
  }

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<layout::Triangle> one_sided_;  // the triangles, kept for the side test when one-sided
  std::size_t triangles_ = 0;
  std::once_flag commit_;
  std::atomic<bool> committed_{false};
};

}  // namespace

std::unique_ptr<Tracer> MakeEmbreeTracer(const SceneBuffers& scene, int threads) {
  return std::make_unique<EmbreeTracer>(scene, threads);
}

}  // namespace rayspace::refs
