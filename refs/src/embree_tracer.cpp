#include "rayspace/refs/embree_tracer.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rayspace/emu/intersect.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::refs {
namespace {

constexpr const char* kIsa = "sse4.2";

// The context carries the primitive a ray must ignore (the surface it leaves), like the emulator.
struct Context {
  RTCIntersectContext base;
  std::uint32_t ignore;
};

void IgnoreFilter(const RTCFilterFunctionNArguments* args) {
  const auto* ctx = reinterpret_cast<const Context*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    if (RTCHitN_primID(args->hit, args->N, i) == ctx->ignore) args->valid[i] = 0;
  }
}

class EmbreeTracer final : public Tracer {
 public:
  EmbreeTracer(const SceneBuffers& scene, int threads) {
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
    rtcSetGeometryIntersectFilterFunction(geom, IgnoreFilter);
    rtcSetGeometryOccludedFilterFunction(geom, IgnoreFilter);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw std::runtime_error("Embree scene build failed");
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
  }

  void Closest(const std::vector<layout::Ray>& rays, std::vector<std::uint64_t>& hits) override {
    hits.assign(rays.size(), emu::kMissPacked);
    ParallelFor(rays.size(), [&](std::size_t i) {
      Context ctx;
      rtcInitIntersectContext(&ctx.base);
      ctx.ignore = rays[i].info.y;
      RTCRayHit rh{};
      Fill(rays[i], rh.ray);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene_, &ctx.base, &rh);
      if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) hits[i] = emu::PackHit(rh.ray.tfar, rh.hit.primID);
    });
  }

  void Occluded(const std::vector<layout::Ray>& rays, std::vector<std::uint32_t>& occluded) override {
    occluded.assign(rays.size(), 0u);
    ParallelFor(rays.size(), [&](std::size_t i) {
      Context ctx;
      rtcInitIntersectContext(&ctx.base);
      ctx.ignore = rays[i].info.y;
      RTCRay r{};
      Fill(rays[i], r);
      rtcOccluded1(scene_, &ctx.base, &r);
      occluded[i] = r.tfar == -INFINITY ? 1u : 0u;
    });
  }

 private:
  static void Fill(const layout::Ray& in, RTCRay& r) {
    r.org_x = in.origin_tmin.x;
    r.org_y = in.origin_tmin.y;
    r.org_z = in.origin_tmin.z;
    r.tnear = in.origin_tmin.w;
    r.dir_x = in.direction_tmax.x;
    r.dir_y = in.direction_tmax.y;
    r.dir_z = in.direction_tmax.z;
    r.tfar = in.direction_tmax.w;
    r.mask = ~0u;
    r.flags = 0;
    r.time = 0;
  }

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

}  // namespace

std::unique_ptr<Tracer> MakeEmbreeTracer(const SceneBuffers& scene, int threads) {
  return std::make_unique<EmbreeTracer>(scene, threads);
}

}  // namespace rayspace::refs
