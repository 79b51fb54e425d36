#include "rayspace/procedural.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "json_checks.h"
#include "rayspace/error.h"

namespace rayspace {
namespace {

using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;
// Keeps lengths well inside float range so products and squared distances cannot overflow.
constexpr double kMaxLength = 1e6;

void AddTriangle(SubMesh& m, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 na, glm::vec3 nb,
                 glm::vec3 nc) {
  m.positions.insert(m.positions.end(), {a, b, c});
  m.normals.insert(m.normals.end(), {na, nb, nc});
  m.material.push_back(-1);
}

// t = i / n, but exactly 0 and 1 at the ends so neighbouring patches share their edge vertices.
double Fraction(int i, int n) { return i == n ? 1.0 : static_cast<double>(i) / n; }

float Lerp(float lo, float hi, int i, int n) {
  if (i == 0) return lo;
  if (i == n) return hi;
  return static_cast<float>(lo + (static_cast<double>(hi) - lo) * Fraction(i, n));
}

// One axis-aligned face in the plane coord[axis] = plane, spanning [lo, hi] on the other two axes,
// split n x n, normal along +axis (sign > 0) or -axis. The in-plane axes u, v are picked so that
// u x v equals the normal; stepping +u then +v is then counter-clockwise seen from the normal.
void AppendGridFace(SubMesh& m, int axis, int sign, float plane, glm::vec3 lo, glm::vec3 hi, int n) {
  int u = (axis + 1) % 3;
  int v = (axis + 2) % 3;
  if (sign < 0) std::swap(u, v);
  glm::vec3 normal(0.0f);
  normal[axis] = sign > 0 ? 1.0f : -1.0f;
  auto point = [&](int i, int j) {
    glm::vec3 p;
    p[axis] = plane;
    p[u] = Lerp(lo[u], hi[u], i, n);
    p[v] = Lerp(lo[v], hi[v], j, n);
    return p;
  };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      glm::vec3 p00 = point(i, j), p10 = point(i + 1, j), p11 = point(i + 1, j + 1), p01 = point(i, j + 1);
      AddTriangle(m, p00, p10, p11, normal, normal, normal);
      AddTriangle(m, p00, p11, p01, normal, normal, normal);
    }
  }
}

void AppendBox(SubMesh& m, glm::vec3 lo, glm::vec3 hi, int n, bool inward) {
  for (int axis = 0; axis < 3; ++axis) {
    for (int side : {+1, -1}) {
      int sign = inward ? -side : side;
      AppendGridFace(m, axis, sign, side > 0 ? hi[axis] : lo[axis], lo, hi, n);
    }
  }
}

// cos and sin of 2 pi k / segments for k = 0..segments, with the last equal to the first so the
// seam closes exactly.
struct Circle {
  std::vector<double> c, s;
  explicit Circle(int segments) : c(segments + 1), s(segments + 1) {
    for (int k = 0; k < segments; ++k) {
      double phi = 2.0 * kPi * k / segments;
      c[k] = std::cos(phi);
      s[k] = std::sin(phi);
    }
    c[segments] = c[0];
    s[segments] = s[0];
  }
};

// Points on the circle go from +X towards +Z. Seen from +Y that turns clockwise, which is why the
// top cap and the side walk the segment index backwards relative to the bottom cap.
void AppendCylinder(SubMesh& m, float radius, float height, int segments, bool caps) {
  Circle circle(segments);
  auto rim = [&](int k, float y) {
    return glm::vec3(static_cast<float>(radius * circle.c[k]), y, static_cast<float>(radius * circle.s[k]));
  };
  auto radial = [&](int k) {
    return glm::vec3(static_cast<float>(circle.c[k]), 0.0f, static_cast<float>(circle.s[k]));
  };
  for (int k = 0; k < segments; ++k) {
    glm::vec3 t0 = rim(k, height), t1 = rim(k + 1, height), b0 = rim(k, 0.0f), b1 = rim(k + 1, 0.0f);
    glm::vec3 n0 = radial(k), n1 = radial(k + 1);
    AddTriangle(m, t0, t1, b1, n0, n1, n1);
    AddTriangle(m, t0, b1, b0, n0, n1, n0);
  }
  if (!caps) return;
  const glm::vec3 up(0, 1, 0), down(0, -1, 0);
  const glm::vec3 top_centre(0, height, 0), bottom_centre(0, 0, 0);
  for (int k = 0; k < segments; ++k) {
    AddTriangle(m, top_centre, rim(k + 1, height), rim(k, height), up, up, up);
    AddTriangle(m, bottom_centre, rim(k, 0.0f), rim(k + 1, 0.0f), down, down, down);
  }
}

// Copies `part` into `dst` rotated by `rotation` and then moved by `offset`.
void AppendPlaced(SubMesh& dst, const SubMesh& part, const glm::mat3& rotation, glm::vec3 offset) {
  for (std::size_t i = 0; i < part.positions.size(); ++i) {
    dst.positions.push_back(rotation * part.positions[i] + offset);
    dst.normals.push_back(glm::normalize(rotation * part.normals[i]));
  }
  dst.material.insert(dst.material.end(), part.material.begin(), part.material.end());
}

glm::mat3 RotationY(double degrees) {
  double a = degrees * kPi / 180.0;
  float c = static_cast<float>(std::cos(a)), s = static_cast<float>(std::sin(a));
  // Column-major: columns are the images of X, Y and Z.
  return glm::mat3(glm::vec3(c, 0, -s), glm::vec3(0, 1, 0), glm::vec3(s, 0, c));
}

// Builder for the furniture pieces: every box and cylinder shares the piece's tessellation.
class Assembly {
 public:
  Assembly(int detail, const std::string& name) : detail_(detail) {
    RS_CHECK(detail >= 1 && detail <= 64);
    mesh_.name = name;
  }
  // Box with half extents `half` centred at `centre`, turned `yaw_deg` about its vertical axis.
  void Box(glm::vec3 centre, glm::vec3 half, double yaw_deg = 0.0) {
    SubMesh part;
    AppendBox(part, -half, half, detail_, false);
    AppendPlaced(mesh_, part, RotationY(yaw_deg), centre);
  }
  void BoxSpan(glm::vec3 lo, glm::vec3 hi) { Box(0.5f * (lo + hi), 0.5f * (hi - lo)); }
  // Upright capped cylinder standing on `base`.
  void Cylinder(glm::vec3 base, float radius, float height) {
    SubMesh part;
    AppendCylinder(part, radius, height, 8 * detail_, true);
    AppendPlaced(mesh_, part, glm::mat3(1.0f), base);
  }
  MeshData Finish() {
    MeshData data;
    data.submeshes.push_back(std::move(mesh_));
    return data;
  }

 private:
  int detail_;
  SubMesh mesh_;
};

MeshData Single(SubMesh&& m) {
  MeshData data;
  data.submeshes.push_back(std::move(m));
  return data;
}

// ---- Parameter parsing ---------------------------------------------------------------------

// A generator's params, read with the scene loader's checked readers: errors read
// "scene.json: objects[3]: generator 'sphere': params.segments: 2 out of range [3, 4096]".
class Params {
 public:
  Params(const json& params, const std::string& kind, const std::string& where,
         std::initializer_list<const char*> known)
      : params_(params), c_{fmt::format("{}: generator '{}'", where, kind)} {
    if (params_.is_null()) return;
    json_checks::CheckKeys(c_, params_, "params", known);
  }

  int Int(const char* key, int fallback, int lo, int hi) const {
    const json* v = Find(key);
    return v ? json_checks::Integer(c_, *v, Field(key), lo, hi, true) : fallback;
  }

  // A length or similar: finite, above 0 (or at least 0 when !positive) and at most kMaxLength.
  float Number(const char* key, float fallback, bool positive) const {
    const json* v = Find(key);
    return v ? static_cast<float>(json_checks::Number(c_, *v, Field(key), 0.0, kMaxLength, positive)) : fallback;
  }

  // A number (the same on all three axes) or an array of three numbers, each positive.
  glm::vec3 Size(const char* key, glm::vec3 fallback) const {
    const json* v = Find(key);
    if (!v) return fallback;
    if (v->is_number()) return glm::vec3(static_cast<float>(json_checks::Number(c_, *v, Field(key), 0.0, kMaxLength, true)));
    return json_checks::Vec3(c_, *v, Field(key), 0.0, kMaxLength, true);
  }

  bool Bool(const char* key, bool fallback) const {
    const json* v = Find(key);
    return v ? json_checks::Bool(c_, *v, Field(key)) : fallback;
  }

  void LimitTriangles(const char* key, std::uint64_t triangles) const {
    if (triangles >= kMaxGeneratedTriangles) {
      c_.Fail(Field(key), fmt::format("would make {} triangles, the limit is {}", triangles, kMaxGeneratedTriangles - 1));
    }
  }

 private:
  static std::string Field(const char* key) { return std::string("params.") + key; }

  const json* Find(const char* key) const {
    if (!params_.is_object()) return nullptr;
    auto it = params_.find(key);
    return it == params_.end() ? nullptr : &*it;
  }

  const json& params_;
  json_checks::Ctx c_;
};

using u64 = std::uint64_t;

}  // namespace

MeshData GenerateBox(glm::vec3 size, int subdivisions, bool inward, const std::string& name) {
  RS_CHECK(subdivisions >= 1);
  SubMesh m;
  m.name = name;
  AppendBox(m, -0.5f * size, 0.5f * size, subdivisions, inward);
  return Single(std::move(m));
}

// Latitude theta runs from the +Y pole (ring 0) to the -Y pole; longitude phi from +X towards +Z.
// d/dphi x d/dtheta points outward, so (s, r) -> (s+1, r) -> (s+1, r+1) is counter-clockwise
// seen from outside.
MeshData GenerateSphere(float radius, int segments, int rings, const std::string& name) {
  RS_CHECK(segments >= 3 && rings >= 2 && radius > 0.0f);
  SubMesh m;
  m.name = name;
  Circle circle(segments);
  std::vector<double> ring_sin(rings + 1), ring_cos(rings + 1);
  for (int r = 0; r <= rings; ++r) {
    double theta = kPi * r / rings;
    ring_sin[r] = std::sin(theta);
    ring_cos[r] = std::cos(theta);
  }
  ring_sin[0] = ring_sin[rings] = 0.0;
  ring_cos[0] = 1.0;
  ring_cos[rings] = -1.0;
  auto normal = [&](int s, int r) {
    return glm::vec3(static_cast<float>(ring_sin[r] * circle.c[s]), static_cast<float>(ring_cos[r]),
                     static_cast<float>(ring_sin[r] * circle.s[s]));
  };
  auto point = [&](int s, int r) {
    return glm::vec3(static_cast<float>(radius * ring_sin[r] * circle.c[s]),
                     static_cast<float>(radius * ring_cos[r]),
                     static_cast<float>(radius * ring_sin[r] * circle.s[s]));
  };
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      glm::vec3 p00 = point(s, r), p10 = point(s + 1, r), p11 = point(s + 1, r + 1), p01 = point(s, r + 1);
      glm::vec3 n00 = normal(s, r), n10 = normal(s + 1, r), n11 = normal(s + 1, r + 1), n01 = normal(s, r + 1);
      // At the poles one of the two triangles collapses; leave it out.
      if (r != 0) AddTriangle(m, p00, p10, p11, n00, n10, n11);
      if (r != rings - 1) AddTriangle(m, p00, p11, p01, n00, n11, n01);
    }
  }
  return Single(std::move(m));
}

MeshData GenerateCylinder(float radius, float height, int segments, bool caps, const std::string& name) {
  RS_CHECK(segments >= 3 && radius > 0.0f && height > 0.0f);
  SubMesh m;
  m.name = name;
  AppendCylinder(m, radius, height, segments, caps);
  return Single(std::move(m));
}

MeshData GenerateWavy(float size, float amplitude, float frequency, int resolution, const std::string& name) {
  RS_CHECK(resolution >= 1 && size > 0.0f);
  SubMesh m;
  m.name = name;
  const double half = 0.5 * size;
  const double a = amplitude, f = frequency;
  auto coord = [&](int i) { return i == resolution ? half : -half + size * Fraction(i, resolution); };
  auto point = [&](int ix, int iz) {
    double x = coord(ix), z = coord(iz);
    return glm::vec3(static_cast<float>(x), static_cast<float>(a * std::cos(f * x) * std::cos(f * z)),
                     static_cast<float>(z));
  };
  auto normal = [&](int ix, int iz) {
    double x = coord(ix), z = coord(iz);
    double dydx = -a * f * std::sin(f * x) * std::cos(f * z);
    double dydz = -a * f * std::cos(f * x) * std::sin(f * z);
    double len = std::sqrt(dydx * dydx + 1.0 + dydz * dydz);
    return glm::vec3(static_cast<float>(-dydx / len), static_cast<float>(1.0 / len), static_cast<float>(-dydz / len));
  };
  // Z x X = +Y: stepping +z then +x is counter-clockwise seen from above.
  for (int ix = 0; ix < resolution; ++ix) {
    for (int iz = 0; iz < resolution; ++iz) {
      glm::vec3 p00 = point(ix, iz), p10 = point(ix, iz + 1), p11 = point(ix + 1, iz + 1), p01 = point(ix + 1, iz);
      glm::vec3 n00 = normal(ix, iz), n10 = normal(ix, iz + 1), n11 = normal(ix + 1, iz + 1), n01 = normal(ix + 1, iz);
      AddTriangle(m, p00, p10, p11, n00, n10, n11);
      AddTriangle(m, p00, p11, p01, n00, n11, n01);
    }
  }
  return Single(std::move(m));
}

// Published Cornell box: the camera looks along +Z, so the left (red) wall is at x = 556 and the
// right (green) wall at x = 0.
MeshData GenerateCornellRoom(int subdivisions, bool closed) {
  RS_CHECK(subdivisions >= 1);
  const glm::vec3 lo(0.0f), hi(556.0f, 548.8f, 559.2f);
  struct Wall {
    const char* name;
    int axis, sign;
    float plane;
  };
  const std::array<Wall, 6> walls{{
      {"floor", 1, +1, lo.y},
      {"ceiling", 1, -1, hi.y},
      {"back", 2, -1, hi.z},
      {"front", 2, +1, lo.z},
      {"left", 0, -1, hi.x},
      {"right", 0, +1, lo.x},
  }};
  MeshData data;
  for (const Wall& w : walls) {
    if (!closed && std::string_view(w.name) == "front") continue;
    SubMesh m;
    m.name = w.name;
    AppendGridFace(m, w.axis, w.sign, w.plane, lo, hi, subdivisions);
    data.submeshes.push_back(std::move(m));
  }
  return data;
}

MeshData GenerateDesk(int detail, const std::string& name) {
  Assembly a(detail, name);
  a.BoxSpan({-0.70f, 0.72f, -0.35f}, {0.70f, 0.75f, 0.35f});    // top
  a.BoxSpan({0.20f, 0.0f, -0.30f}, {0.60f, 0.72f, 0.28f});      // drawer pedestal
  a.BoxSpan({-0.60f, 0.30f, -0.33f}, {0.60f, 0.72f, -0.31f});   // modesty panel
  for (float x : {-0.65f, 0.65f}) {
    for (float z : {-0.30f, 0.30f}) a.Cylinder({x, 0.0f, z}, 0.025f, 0.72f);
  }
  return a.Finish();
}

MeshData GenerateChair(int detail, const std::string& name) {
  Assembly a(detail, name);
  a.BoxSpan({-0.24f, 0.435f, -0.23f}, {0.24f, 0.505f, 0.23f});  // seat
  a.BoxSpan({-0.23f, 0.57f, -0.29f}, {0.23f, 1.07f, -0.24f});   // backrest
  a.BoxSpan({-0.03f, 0.46f, -0.27f}, {0.03f, 0.60f, -0.24f});   // backrest support
  a.Cylinder({0.0f, 0.10f, 0.0f}, 0.025f, 0.335f);              // gas column
  for (int k = 0; k < 5; ++k) {
    double yaw = 90.0 + 72.0 * k;
    glm::mat3 turn = RotationY(yaw);
    // Legs lie along local +X before turning.
    a.Box(turn * glm::vec3(0.15f, 0.08f, 0.0f), {0.15f, 0.02f, 0.025f}, yaw);
    a.Cylinder(turn * glm::vec3(0.28f, 0.0f, 0.0f), 0.03f, 0.06f);  // caster
  }
  return a.Finish();
}

MeshData GenerateShelf(int detail, const std::string& name) {
  Assembly a(detail, name);
  const float w = 0.45f, h = 1.90f, d = 0.175f, t = 0.02f;
  a.BoxSpan({-w, 0.0f, -d}, {-w + t, h, d});           // sides
  a.BoxSpan({w - t, 0.0f, -d}, {w, h, d});
  a.BoxSpan({-w + t, h - t, -d}, {w - t, h, d});       // top
  a.BoxSpan({-w + t, 0.0f, -d}, {w - t, 0.08f, d});    // plinth
  a.BoxSpan({-w + t, 0.08f, -d}, {w - t, h - t, -d + 0.01f});  // back panel
  // Shelf boards split the inside into four equal compartments.
  const float bottom = 0.08f, top = h - t, pitch = (top - bottom) / 4.0f;
  for (int k = 1; k < 4; ++k) {
    float y = bottom + pitch * k;
    a.BoxSpan({-w + t, y - t, -d + 0.01f}, {w - t, y, d});
  }
  // Five books per compartment; sizes vary deterministically so rows do not look stamped.
  const std::array<float, 5> widths{0.05f, 0.07f, 0.04f, 0.06f, 0.08f};
  const std::array<float, 5> heights{0.26f, 0.30f, 0.22f, 0.28f, 0.24f};
  for (int level = 0; level < 4; ++level) {
    float y0 = bottom + pitch * level;
    float x = -w + t + 0.03f + 0.05f * level;
    for (int b = 0; b < 5; ++b) {
      int k = (b + level) % 5;
      a.BoxSpan({x, y0, -d + 0.03f}, {x + widths[k], y0 + heights[k], d - 0.05f + 0.01f * k});
      x += widths[k] + 0.01f;
    }
  }
  return a.Finish();
}

MeshData GenerateMonitor(int detail, const std::string& name) {
  Assembly a(detail, name);
  a.BoxSpan({-0.265f, 0.12f, -0.0125f}, {0.265f, 0.44f, 0.0125f});  // panel
  a.BoxSpan({-0.025f, 0.015f, -0.045f}, {0.025f, 0.20f, -0.0125f});  // neck
  a.Cylinder({0.0f, 0.0f, -0.03f}, 0.10f, 0.015f);                   // foot
  return a.Finish();
}

MeshData GenerateLamp(int detail, const std::string& name) {
  Assembly a(detail, name);
  a.Cylinder({0.0f, 0.0f, 0.0f}, 0.075f, 0.02f);                   // foot
  a.Cylinder({0.0f, 0.02f, 0.0f}, 0.010f, 0.40f);                  // upright
  a.BoxSpan({-0.01f, 0.42f, -0.01f}, {0.01f, 0.44f, 0.28f});       // arm
  a.Cylinder({0.0f, 0.32f, 0.28f}, 0.06f, 0.10f);                  // shade
  return a.Finish();
}

MeshData Generate(const std::string& kind, const nlohmann::json& params, const std::string& where) {
  if (kind == "box") {
    Params p(params, kind, where, {"size", "subdivisions", "inward"});
    glm::vec3 size = p.Size("size", glm::vec3(1.0f));
    int n = p.Int("subdivisions", 1, 1, 1024);
    bool inward = p.Bool("inward", false);
    p.LimitTriangles("subdivisions", u64{12} * n * n);
    return GenerateBox(size, n, inward, kind);
  }
  if (kind == "sphere") {
    Params p(params, kind, where, {"radius", "segments", "rings"});
    float radius = p.Number("radius", 1.0f, true);
    int segments = p.Int("segments", 32, 3, 4096);
    int rings = p.Int("rings", 16, 2, 4096);
    p.LimitTriangles("segments", u64{2} * segments * (rings - 1));
    return GenerateSphere(radius, segments, rings, kind);
  }
  if (kind == "cylinder") {
    Params p(params, kind, where, {"radius", "height", "segments", "caps"});
    float radius = p.Number("radius", 0.5f, true);
    float height = p.Number("height", 1.0f, true);
    int segments = p.Int("segments", 32, 3, 4096);
    bool caps = p.Bool("caps", true);
    return GenerateCylinder(radius, height, segments, caps, kind);
  }
  if (kind == "wavy") {
    Params p(params, kind, where, {"size", "amplitude", "frequency", "resolution"});
    float size = p.Number("size", 1.0f, true);
    float amplitude = p.Number("amplitude", 0.05f, false);
    float frequency = p.Number("frequency", 10.0f, false);
    int resolution = p.Int("resolution", 32, 1, 4096);
    p.LimitTriangles("resolution", u64{2} * resolution * resolution);
    return GenerateWavy(size, amplitude, frequency, resolution, kind);
  }
  if (kind == "cornell_room") {
    Params p(params, kind, where, {"subdivisions", "closed"});
    int n = p.Int("subdivisions", 1, 1, 1024);
    bool closed = p.Bool("closed", true);
    p.LimitTriangles("subdivisions", u64{closed ? 6u : 5u} * 2 * n * n);
    return GenerateCornellRoom(n, closed);
  }
  using Furniture = MeshData (*)(int, const std::string&);
  static constexpr std::array<std::pair<std::string_view, Furniture>, 5> furniture{{
      {"desk", &GenerateDesk},
      {"chair", &GenerateChair},
      {"shelf", &GenerateShelf},
      {"monitor", &GenerateMonitor},
      {"lamp", &GenerateLamp},
  }};
  for (const auto& [name, generate] : furniture) {
    if (kind != name) continue;
    Params p(params, kind, where, {"detail"});
    // 64 keeps the largest piece (the shelf) far below the triangle limit.
    int detail = p.Int("detail", 2, 1, 64);
    return generate(detail, kind);
  }
  ThrowInput("{}: unknown generator '{}' (known: box, sphere, cylinder, wavy, cornell_room, desk, chair, "
             "shelf, monitor, lamp)",
             where, kind);
}

}  // namespace rayspace
