// MRT raster following lavapipe's (Mesa 22.3, llvmpipe) recipe; see docs/raster.md.
//
// Coverage follows lavapipe's fixed-point setup: fused viewport transform, 8 subpixel bits, 64-bit
// edge functions with the top-left rule, and Mesa's C clipper for triangles that cross the clip volume
// (a depth attachment disables the guard band). Position, normal and depth are not interpolated:
// the fragment stage reconstructs them from the primitive id and the pixel-centre ray with plain
// IEEE operations and writes gl_FragDepth, so no attribute-interpolation emulation is needed.
// The whole draw path runs with FTZ/DAZ, as lavapipe does.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/raster_detail.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {
namespace raster {

glm::vec4 VertexStage(const glm::mat4& m, glm::vec3 p) {
  glm::vec4 c;
  for (int r = 0; r < 4; ++r) {
    // (((m0*x + m1*y) + m2*z) + m3): w = 1 is not multiplied (lavapipe folds x*1.0 to x).
    const float a = m[0][r] * p.x;
    const float b = m[1][r] * p.y;
    const float d = m[2][r] * p.z;
    c[r] = ((a + b) + d) + m[3][r];
  }
  return c;
}

namespace {

// Mesa's draw module clip planes in the order it tests them (halfz depth: 0 <= z <= w).
constexpr float kPlanes[6][4] = {
    {1, 0, 0, 1}, {-1, 0, 0, 1}, {0, 1, 0, 1}, {0, -1, 0, 1}, {0, 0, 1, 0}, {0, 0, -1, 1},
};

float ClipDist(const glm::vec4& c, int plane) {
  const float* p = kPlanes[plane];
  return ((c.x * p[0] + c.y * p[1]) + c.z * p[2]) + c.w * p[3];
}

bool IsNegative(float x) { return x < 0.0f; }
bool DifferentSigns(float x, float y) { return x * y <= 0.0f && x - y != 0.0f; }

}  // namespace

glm::vec2 WindowFused(const glm::vec4& c, float half_w, float half_h) {
  const float oow = 1.0f / c.w;
  return {std::fmaf(c.x * oow, half_w, half_w), std::fmaf(c.y * oow, half_h, half_h)};
}

glm::vec2 WindowUnfused(const glm::vec4& c, float half_w, float half_h) {
  const float oow = 1.0f / c.w;
  return {(c.x * oow) * half_w + half_w, (c.y * oow) * half_h + half_h};
}

int ClipTriangle(const std::array<glm::vec4, 3>& in, float half_w, float half_h, std::array<glm::vec2, kMaxClipVerts>& out) {
  unsigned mask[3] = {0, 0, 0};
  for (int v = 0; v < 3; ++v)
    for (int p = 0; p < 6; ++p)
      if (IsNegative(ClipDist(in[v], p))) mask[v] |= 1u << p;
  if (mask[0] & mask[1] & mask[2]) return 0;  // entirely outside one plane
  if ((mask[0] | mask[1] | mask[2]) == 0) {
    for (int v = 0; v < 3; ++v) out[v] = WindowFused(in[v], half_w, half_h);
    return 3;
  }
  struct V {
    glm::vec4 clip;
    bool created;
    int original;
  };
  std::array<V, kMaxClipVerts> a{}, b{};
  int n = 3;
  for (int v = 0; v < 3; ++v) a[v] = {in[v], false, v};
  const unsigned planes = mask[0] | mask[1] | mask[2];
  for (int p = 0; p < 6 && n > 0; ++p) {
    if (!(planes & (1u << p))) continue;
    int m = 0;
    V prev = a[n - 1];
    float dp_prev = ClipDist(prev.clip, p);
    for (int i = 0; i < n; ++i) {
      const V cur = a[i];
      const float dp = ClipDist(cur.clip, p);
      if (!IsNegative(dp_prev)) b[m++] = prev;
      if (DifferentSigns(dp, dp_prev)) {
        // Mesa's interp(): out + t * (in - out), t measured from the outside vertex.
        const V& outside = IsNegative(dp) ? cur : prev;
        const V& inside = IsNegative(dp) ? prev : cur;
        const float t = IsNegative(dp) ? dp / (dp - dp_prev) : dp_prev / (dp_prev - dp);
        V nv{};
        for (int k = 0; k < 4; ++k) nv.clip[k] = outside.clip[k] + t * (inside.clip[k] - outside.clip[k]);
        nv.created = true;
        nv.original = -1;
        RS_CHECK(m < kMaxClipVerts);
        b[m++] = nv;
      }
      prev = cur;
      dp_prev = dp;
    }
    a = b;
    n = m;
  }
  for (int i = 0; i < n; ++i)
    out[i] = a[i].created ? WindowUnfused(a[i].clip, half_w, half_h) : WindowFused(a[i].clip, half_w, half_h);
  return n < 3 ? 0 : n;
}

bool SetupTriangle(glm::vec2 w0, glm::vec2 w1, glm::vec2 w2, int width, int height, Setup& s) {
  const glm::vec2 w[3] = {w0, w1, w2};
  std::int64_t X[3], Y[3];
  for (int k = 0; k < 3; ++k) {
    X[k] = static_cast<std::int64_t>(std::nearbyint((w[k].x - 0.5f) * 256.0f));
    Y[k] = static_cast<std::int64_t>(std::nearbyint((w[k].y - 0.5f) * 256.0f));
  }
  // Signed area as the first edge function evaluated at the third vertex.
  const std::int64_t area = (Y[0] - Y[1]) * X[0] - (X[0] - X[1]) * Y[0] - (Y[0] - Y[1]) * X[2] + (X[0] - X[1]) * Y[2];
  if (area == 0) return false;
  if (area < 0) {
    std::swap(X[1], X[2]);
    std::swap(Y[1], Y[2]);
  }
  for (int e = 0; e < 3; ++e) {
    const int i = e, j = (e + 1) % 3;
    s.dcdx[e] = Y[i] - Y[j];
    s.dcdy[e] = X[i] - X[j];
    s.c[e] = s.dcdx[e] * X[i] - s.dcdy[e] * Y[i];
    if (s.dcdx[e] < 0 || (s.dcdx[e] == 0 && s.dcdy[e] > 0)) s.c[e] += 1;  // top-left rule
  }
  const std::int64_t minx = std::min({X[0], X[1], X[2]}), maxx = std::max({X[0], X[1], X[2]});
  const std::int64_t miny = std::min({Y[0], Y[1], Y[2]}), maxy = std::max({Y[0], Y[1], Y[2]});
  auto ceil_div = [](std::int64_t a) { return a >= 0 ? (a + 255) / 256 : -((-a) / 256); };
  auto floor_div = [](std::int64_t a) { return a >= 0 ? a / 256 : -((-a + 255) / 256); };
  s.x0 = static_cast<int>(std::max<std::int64_t>(0, ceil_div(minx)));
  s.x1 = static_cast<int>(std::min<std::int64_t>(width - 1, floor_div(maxx)));
  s.y0 = static_cast<int>(std::max<std::int64_t>(0, ceil_div(miny)));
  s.y1 = static_cast<int>(std::min<std::int64_t>(height - 1, floor_div(maxy)));
  return s.x0 <= s.x1 && s.y0 <= s.y1;
}

bool Covers(const Setup& s, int px, int py) {
  const std::int64_t x = static_cast<std::int64_t>(px) << 8, y = static_cast<std::int64_t>(py) << 8;
  for (int e = 0; e < 3; ++e)
    if (s.c[e] - s.dcdx[e] * x + s.dcdy[e] * y <= 0) return false;
  return true;
}

std::vector<Setup> SetupAll(const layout::FrameConstants& fc, const std::vector<layout::Triangle>& tris) {
  const int width = static_cast<int>(fc.dims.x), height = static_cast<int>(fc.dims.y);
  const float half_w = 0.5f * static_cast<float>(width), half_h = 0.5f * static_cast<float>(height);
  const auto clip_window = [&](std::size_t i, std::array<glm::vec2, kMaxClipVerts>& win) {
    const layout::Triangle& t = tris[i];
    const std::array<glm::vec4, 3> clip = {VertexStage(fc.view_proj, Xyz(t.v0)), VertexStage(fc.view_proj, Xyz(t.v1)),
                                           VertexStage(fc.view_proj, Xyz(t.v2))};
    return ClipTriangle(clip, half_w, half_h, win);
  };
  // Two passes over the primitives, so that memory holds one setup per fan triangle rather than room
  // for kMaxClipVerts - 2 per primitive (a scene of many triangles would hold 672 bytes for each):
  // the fan sizes, then the setups at their primitive's offset, compacted in primitive order.
  std::vector<std::uint8_t> fans(tris.size(), 0);
  ParallelForFtz(tris.size(), [&](std::size_t i) {
    std::array<glm::vec2, kMaxClipVerts> win;
    fans[i] = static_cast<std::uint8_t>(std::max(clip_window(i, win) - 2, 0));
  });
  std::vector<std::size_t> offset(tris.size() + 1, 0);
  for (std::size_t i = 0; i < tris.size(); ++i) offset[i + 1] = offset[i] + fans[i];
  std::vector<Setup> out(offset.back());
  ParallelForFtz(tris.size(), [&](std::size_t i) {
    std::array<glm::vec2, kMaxClipVerts> win;
    const int n = clip_window(i, win);  // the same polygon as the first pass: the same arithmetic
    int k = 0;
    for (int f = 2; f < n; ++f) {  // fan (0, f-1, f)
      Setup s;
      s.prim = static_cast<std::uint32_t>(i);
      if (SetupTriangle(win[0], win[f - 1], win[f], width, height, s)) out[offset[i] + k++] = s;
    }
    fans[i] = static_cast<std::uint8_t>(k);  // the setups kept, at most the fan's size
  });
  std::size_t kept = 0;
  for (std::size_t i = 0; i < tris.size(); ++i)
    for (int k = 0; k < fans[i]; ++k) out[kept++] = out[offset[i] + k];  // kept <= offset[i] + k
  out.resize(kept);
  return out;
}

Fragment ShadeFragment(const layout::FrameConstants& fc, const SceneBuffers& scene, std::uint32_t prim, int px, int py) {
  const layout::Triangle& t = scene.triangles[prim];
  const glm::vec3 d = PixelDirection(fc, static_cast<std::uint32_t>(px), static_cast<std::uint32_t>(py));
  return ShadeFragmentOf(fc, Xyz(t.v0), Xyz(t.v1), Xyz(t.v2), d);
}

}  // namespace raster

GBuffer PassRaster(const call::Raster& c) {
  const layout::FrameConstants& fc = c.frame;
  const SceneBuffers& scene = *c.scene;
  using namespace raster;
  const int width = static_cast<int>(fc.dims.x), height = static_cast<int>(fc.dims.y);
  GBuffer g;
  g.width = width;
  g.height = height;
  const std::size_t npix = static_cast<std::size_t>(width) * height;
  g.diffuse.assign(npix, glm::vec4(0));
  g.specular.assign(npix, glm::vec4(0));
  g.position.assign(npix, glm::vec4(0));
  g.normal.assign(npix, glm::vec4(0));
  g.prim.assign(npix, layout::kNoPrim);
  g.depth.assign(npix, 1.0f);

  const std::vector<Setup> setups = SetupAll(fc, scene.triangles);

  // Bands of rows; each band walks all primitives in order, so the depth test sees fragments in
  // primitive order whatever the thread count (LESS: the first of equal depths stays).
  constexpr int kBand = 8;
  const int bands = (height + kBand - 1) / kBand;
  ParallelForFtz(static_cast<std::size_t>(bands), [&](std::size_t b) {
    const int ylo = static_cast<int>(b) * kBand, yhi = std::min(height - 1, ylo + kBand - 1);
    for (const Setup& s : setups) {
      if (s.y1 < ylo || s.y0 > yhi) continue;
      for (int py = std::max(s.y0, ylo); py <= std::min(s.y1, yhi); ++py) {
        for (int px = s.x0; px <= s.x1; ++px) {
          if (!Covers(s, px, py)) continue;
          const Fragment f = ShadeFragment(fc, scene, s.prim, px, py);
          if (f.discard) continue;
          const std::size_t pi = static_cast<std::size_t>(py) * width + px;
          if (!(f.depth < g.depth[pi])) continue;
          g.depth[pi] = f.depth;
          g.prim[pi] = s.prim;
          const layout::Material& m = scene.materials[scene.info[s.prim].ids.x];
          g.diffuse[pi] = m.diffuse_reflectivity;
          g.specular[pi] = m.specular_shininess;
          g.position[pi] = glm::vec4(f.position, 1.0f);
          g.normal[pi] = glm::vec4(ShadingNormal(scene, s.prim, f.position), m.transparency_ior.x);
        }
      }
    }
  });
  return g;
}

}  // namespace rayspace::emu
