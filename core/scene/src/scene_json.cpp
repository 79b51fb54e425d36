// Scene JSON loader. Strict: unknown keys, wrong types and out-of-range values are errors that name
// the file and the field path, because a typo silently ignored renders a different scene.
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/matrix_inverse.hpp>
#include <nlohmann/json.hpp>

#include "json_checks.h"
#include "rayspace/error.h"
#include "rayspace/input_file.h"
#include "rayspace/json_text.h"
#include "rayspace/layout.h"
#include "rayspace/procedural.h"
#include "rayspace/scene.h"

namespace rayspace {
namespace {

bool InDomain(glm::vec3 p) {
  for (int k = 0; k < 3; ++k)
    if (!(std::fabs(static_cast<double>(p[k])) <= kMaxCoordinate)) return false;  // also NaN
  return true;
}

using nlohmann::json;
using json_checks::CheckKeys;
using json_checks::Ctx;
using json_checks::Integer;
using json_checks::Number;
using json_checks::Required;
using json_checks::String;
using json_checks::Vec3;

CameraDesc ParseCamera(const Ctx& c, const json& j) {
  CheckKeys(c, j, "camera", {"eye", "target", "up", "fov_y_deg"});
  CameraDesc cam;
  cam.eye = Vec3(c, Required(c, j, "eye", "camera"), "camera.eye");
  cam.target = Vec3(c, Required(c, j, "target", "camera"), "camera.target");
  if (!InDomain(cam.eye)) c.Fail("camera.eye", "is outside the coordinate domain |x| <= 2^62");
  if (!InDomain(cam.target)) c.Fail("camera.target", "is outside the coordinate domain |x| <= 2^62");
  if (j.contains("up")) cam.up = Vec3(c, j["up"], "camera.up");
  cam.fov_y_deg = static_cast<float>(Number(c, Required(c, j, "fov_y_deg", "camera"), "camera.fov_y_deg", 1.0, 170.0));
  const glm::dvec3 f = glm::dvec3(cam.target) - glm::dvec3(cam.eye);
  if (glm::length(f) == 0.0) c.Fail("camera.target", "equals camera.eye");
  // Any non-zero up not parallel to the view is valid whatever its length: the angle between the
  // two is decided on unit vectors (sin below 1e-6, about 0.2 arc seconds, counts as parallel).
  const glm::dvec3 up(cam.up);
  if (glm::length(up) == 0.0) c.Fail("camera.up", "is zero");
  if (glm::length(glm::cross(glm::normalize(f), glm::normalize(up))) < 1e-6)
    c.Fail("camera.up", "is parallel to the viewing direction");
  return cam;
}

MaterialDesc ParseMaterial(const Ctx& c, const std::string& name, const json& j) {
  const std::string f = "materials." + name;
  CheckKeys(c, j, f, {"diffuse", "specular", "shininess", "reflectivity", "transparency", "ior"});
  MaterialDesc m;
  m.name = name;
  if (j.contains("diffuse")) m.diffuse = Vec3(c, j["diffuse"], f + ".diffuse", 0.0, 1e6);
  if (j.contains("specular")) m.specular = Vec3(c, j["specular"], f + ".specular", 0.0, 1e6);
  if (j.contains("shininess")) m.shininess = static_cast<float>(Integer(c, j["shininess"], f + ".shininess", 0, 4096));
  if (j.contains("reflectivity")) m.reflectivity = static_cast<float>(Number(c, j["reflectivity"], f + ".reflectivity", 0, 1));
  if (j.contains("transparency")) m.transparency = static_cast<float>(Number(c, j["transparency"], f + ".transparency", 0, 1));
  if (j.contains("ior")) m.ior = static_cast<float>(Number(c, j["ior"], f + ".ior", 0.01, 100));
  if (m.reflectivity + m.transparency > 1.0f) c.Fail(f, "reflectivity + transparency exceeds 1");
  return m;
}

// The shape keys of a light: rect needs `size`, disk and sphere `radius`; rect and disk may turn by
// `normal`; an area light draws `samples` points (default 8, as Hunt and Mark's soft shadows).
void ParseLightShape(const Ctx& c, const json& j, const std::string& f, LightDesc& l) {
  static const std::map<std::string, LightShape> kShapes = {
      {"point", LightShape::kPoint}, {"rect", LightShape::kRect}, {"disk", LightShape::kDisk}, {"sphere", LightShape::kSphere}};
  if (j.contains("shape")) {
    const std::string name = String(c, j["shape"], f + ".shape");
    const auto it = kShapes.find(name);
    if (it == kShapes.end()) c.Fail(f + ".shape", fmt::format("unknown shape '{}' (known: point, rect, disk, sphere)", name));
    l.shape = it->second;
  }
  const auto only_for = [&](const char* key, bool allowed, const char* shapes) {
    if (j.contains(key) && !allowed) c.Fail(f + "." + key, fmt::format("only a {} light has one", shapes));
  };
  only_for("size", l.shape == LightShape::kRect, "rect");
  only_for("radius", l.shape == LightShape::kDisk || l.shape == LightShape::kSphere, "disk or sphere");
  only_for("normal", l.shape == LightShape::kRect || l.shape == LightShape::kDisk, "rect or disk");
  only_for("samples", l.IsArea(), "rect, disk or sphere");
  if (l.shape == LightShape::kRect) {
    const json& sj = Required(c, j, "size", f);
    if (!sj.is_array() || sj.size() != 2) c.Fail(f + ".size", fmt::format("expected [width, height], got {}", json_checks::Shown(sj)));
    for (int k = 0; k < 2; ++k)
      l.size[k] = static_cast<float>(Number(c, sj[k], fmt::format("{}.size[{}]", f, k), 0.0, kMaxCoordinate, true));
  }
  if (l.shape == LightShape::kDisk || l.shape == LightShape::kSphere)
    l.radius = static_cast<float>(Number(c, Required(c, j, "radius", f), f + ".radius", 0.0, kMaxCoordinate, true));
  if (j.contains("normal")) {
    const glm::dvec3 n(Vec3(c, j["normal"], f + ".normal"));
    if (!(glm::length(n) > 0.0)) c.Fail(f + ".normal", "is zero");
    l.normal = glm::vec3(glm::normalize(n));
  }
  if (l.IsArea()) l.samples = 8;
  if (j.contains("samples"))
    l.samples = Integer(c, j["samples"], f + ".samples", 1, static_cast<long long>(layout::kMaxLightSamples));
}

LightDesc ParseLight(const Ctx& c, const json& j, const std::string& f) {
  CheckKeys(c, j, f, {"position", "color", "intensity", "attenuation", "shape", "size", "radius", "normal", "samples"});
  LightDesc l;
  l.position = Vec3(c, Required(c, j, "position", f), f + ".position");
  if (!InDomain(l.position)) c.Fail(f + ".position", "is outside the coordinate domain |x| <= 2^62");
  if (j.contains("color")) l.color = Vec3(c, j["color"], f + ".color", 0.0, 1e6);
  if (j.contains("intensity")) l.intensity = static_cast<float>(Number(c, j["intensity"], f + ".intensity", 0.0, 1e12));
  if (j.contains("attenuation")) l.attenuation = Vec3(c, j["attenuation"], f + ".attenuation", 0.0, 1e12);
  if (l.attenuation.x == 0 && l.attenuation.y == 0 && l.attenuation.z == 0)
    c.Fail(f + ".attenuation", "all zero (the light's attenuation would divide by zero)");
  ParseLightShape(c, j, f, l);
  return l;
}

// Object-to-world transform: scale, then rotate about X, Y, Z in that order, then translate.
glm::dmat4 ParseTransform(const Ctx& c, const json& j, const std::string& f) {
  CheckKeys(c, j, f, {"translate", "rotate_deg", "scale"});
  glm::dvec3 t(0), r(0), s(1);
  if (j.contains("translate")) t = Vec3(c, j["translate"], f + ".translate");
  if (j.contains("rotate_deg")) r = Vec3(c, j["rotate_deg"], f + ".rotate_deg", -3600, 3600);
  if (j.contains("scale")) {
    const json& sj = j["scale"];
    if (sj.is_number()) s = glm::dvec3(Number(c, sj, f + ".scale", 1e-12, 1e12));
    else s = Vec3(c, sj, f + ".scale", 1e-12, 1e12);
  }
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), t);
  m = glm::rotate(m, glm::radians(r.z), {0, 0, 1});
  m = glm::rotate(m, glm::radians(r.y), {0, 1, 0});
  m = glm::rotate(m, glm::radians(r.x), {1, 0, 0});
  return glm::scale(m, s);
}

std::filesystem::path ResolveMesh(const Ctx& c, const std::string& field, const std::string& rel,
                                  const std::filesystem::path& scene_dir, const LoadOptions& opt) {
  const std::filesystem::path p(rel);
  std::vector<std::filesystem::path> tried;
  if (p.is_absolute()) {
    tried.push_back(p);
  } else {
    tried.push_back(scene_dir / p);
    std::filesystem::path root = opt.data_root;
    if (root.empty()) {
      if (const char* env = std::getenv("RAYSPACE_DATA")) root = env;
    }
    if (!root.empty()) tried.push_back(root / p);
  }
  // The first path that exists is the mesh, whatever it is: a FIFO or a directory there is refused
  // by the loader with what it is, rather than reported as missing.
  for (const auto& t : tried)
    if (std::error_code ec; std::filesystem::exists(t, ec)) return t;
  std::string list;
  for (const auto& t : tried) list += (list.empty() ? "" : ", ") + t.string();
  c.Fail(field, fmt::format("mesh '{}' not found (looked at {}{})", rel, list,
                            tried.size() < 2 ? "; give a data root with --data DIR or RAYSPACE_DATA" : ""));
}

// Places one sub-mesh in the world. Normals go through the inverse transpose; triangles without
// (usable) vertex normals get their face normal.
Object PlaceSubMesh(const Ctx& c, const std::string& field, const SubMesh& sub, const glm::dmat4& m,
                    const std::vector<std::uint32_t>& material_map, std::uint32_t fixed_material,
                    std::uint32_t default_material) {
  Object o;
  o.name = sub.name;
  const glm::dmat3 nm = glm::inverseTranspose(glm::dmat3(m));
  const std::size_t n = sub.TriangleCount();
  o.positions.resize(3 * n);
  o.normals.resize(3 * n);
  o.material.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    glm::dvec3 w[3];
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = sub.positions[3 * t + k];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        c.Fail(field, fmt::format("sub-mesh '{}' triangle {} has a non-finite vertex", sub.name, t));
      w[k] = glm::dvec3(m * glm::dvec4(glm::dvec3(p), 1.0));
      o.positions[3 * t + k] = glm::vec3(w[k]);
      const glm::vec3& q = o.positions[3 * t + k];
      if (!InDomain(q))
        c.Fail(field, fmt::format("sub-mesh '{}' triangle {} leaves the coordinate domain |x| <= 2^62 after its transform",
                                  sub.name, t));
    }
    glm::dvec3 face = glm::cross(w[1] - w[0], w[2] - w[0]);
    const double fl = glm::length(face);
    face = fl > 0 ? face / fl : glm::dvec3(0, 0, 1);
    for (int k = 0; k < 3; ++k) {
      glm::dvec3 nrm = face;
      if (!sub.normals.empty()) {
        glm::dvec3 v = nm * glm::dvec3(sub.normals[3 * t + k]);
        const double l = glm::length(v);
        if (l > 0 && std::isfinite(l)) nrm = v / l;
      }
      o.normals[3 * t + k] = glm::vec3(nrm);
    }
    if (fixed_material != UINT32_MAX) {
      o.material[t] = fixed_material;
    } else {
      const int local = sub.material.empty() ? -1 : sub.material[t];
      o.material[t] = local >= 0 ? material_map[local] : default_material;
    }
  }
  return o;
}

// The material named "default", added (all defaults) the first time an object needs it.
std::uint32_t DefaultMaterial(Scene& s, std::map<std::string, std::uint32_t>& by_name) {
  auto it = by_name.find("default");
  if (it != by_name.end()) return it->second;
  MaterialDesc d;
  d.name = "default";
  by_name["default"] = static_cast<std::uint32_t>(s.materials.size());
  s.materials.push_back(d);
  return by_name["default"];
}

json ParseFile(const std::filesystem::path& path) {
  const std::string text = ReadInputFile(path, {"scene file", kMaxTextFileBytes});
  json root;
  try {
    root = ParseJson(text);
  } catch (const JsonError& e) {  // syntax errors, number overflow (1e400), depth, duplicate keys, NUL bytes
    ThrowInput("{}: invalid JSON: {}", path.string(), e.what());
  }
  return root;
}

// Lights and materials; `by_name` maps material names to their index in s.materials.
void ParseLightsAndMaterials(const Ctx& c, const json& root, Scene& s, std::map<std::string, std::uint32_t>& by_name) {
  if (root.contains("lights")) {
    const json& lights = root["lights"];
    if (!lights.is_array()) c.Fail("lights", "expected an array");
    if (lights.size() > 255) c.Fail("lights", "more than 255 lights");
    for (std::size_t i = 0; i < lights.size(); ++i)
      s.lights.push_back(ParseLight(c, lights[i], fmt::format("lights[{}]", i)));
    if (ShadowSlotsPerSurface(s.lights) > layout::kMaxShadowSlots)
      c.Fail("lights", fmt::format("{} samples in all (at most {} shadow rays per shading point)",
                                   ShadowSlotsPerSurface(s.lights), layout::kMaxShadowSlots));
  }
  if (root.contains("materials")) {
    const json& mats = root["materials"];
    if (!mats.is_object()) c.Fail("materials", "expected an object mapping names to materials");
    for (auto it = mats.begin(); it != mats.end(); ++it) {
      by_name[it.key()] = static_cast<std::uint32_t>(s.materials.size());
      s.materials.push_back(ParseMaterial(c, it.key(), it.value()));
    }
  }
}

// The object's geometry: its mesh file, or its generator with params.
MeshData ObjectMesh(const Ctx& c, const json& oj, const std::string& f, const std::string& name,
                    const std::filesystem::path& scene_dir, const LoadOptions& options, Scene& s) {
  MeshData mesh;
  if (oj.contains("mesh")) {
    const std::string& rel = String(c, oj["mesh"], f + ".mesh", "a path string");
    const std::filesystem::path mesh_path = ResolveMesh(c, f + ".mesh", rel, scene_dir, options);
    s.files.push_back(mesh_path);
    try {
      mesh = LoadMesh(mesh_path);
    } catch (const InputError& e) {  // name the object too: the mesh may be shared by several
      c.Fail(f + (name.empty() ? "" : " (" + name + ")"), e.what());
    }
  } else {
    const std::string& generator = String(c, oj["generator"], f + ".generator");
    static const json kEmpty = json::object();
    const json& params = oj.contains("params") ? oj["params"] : kEmpty;
    mesh = Generate(generator, params, c.file + ": " + f);
  }
  return mesh;
}

std::vector<glm::dmat4> ObjectTransforms(const Ctx& c, const json& oj, const std::string& f) {
  std::vector<glm::dmat4> transforms;
  if (oj.contains("instances")) {
    const json& inst = oj["instances"];
    if (!inst.is_array() || inst.empty()) c.Fail(f + ".instances", "expected a non-empty array of transforms");
    for (std::size_t k = 0; k < inst.size(); ++k)
      transforms.push_back(ParseTransform(c, inst[k], fmt::format("{}.instances[{}]", f, k)));
  } else {
    transforms.push_back(oj.contains("transform") ? ParseTransform(c, oj["transform"], f + ".transform") : glm::dmat4(1.0));
  }
  return transforms;
}

// objects[i]: its mesh placed once per transform, one Object per sub-mesh and transform.
void AddObject(const Ctx& c, const json& oj, std::size_t i, const std::filesystem::path& scene_dir, const LoadOptions& options,
               Scene& s, std::map<std::string, std::uint32_t>& by_name) {
  const std::string f = fmt::format("objects[{}]", i);
  CheckKeys(c, oj, f, {"name", "mesh", "generator", "params", "transform", "instances", "material"});
  const bool has_mesh = oj.contains("mesh"), has_gen = oj.contains("generator");
  if (has_mesh == has_gen) c.Fail(f, "needs exactly one of 'mesh' or 'generator'");
  if (oj.contains("params") && !has_gen) c.Fail(f + ".params", "only valid with 'generator'");
  if (oj.contains("transform") && oj.contains("instances")) c.Fail(f, "give 'transform' or 'instances', not both");
  const std::string name = oj.contains("name") ? String(c, oj["name"], f + ".name") : std::string();
  const MeshData mesh = ObjectMesh(c, oj, f, name, scene_dir, options, s);

  std::uint32_t fixed = UINT32_MAX;
  if (oj.contains("material")) {
    const std::string& material = String(c, oj["material"], f + ".material", "a material name");
    auto it = by_name.find(material);
    if (it == by_name.end()) c.Fail(f + ".material", fmt::format("unknown material '{}'", material));
    fixed = it->second;
  }
  // Materials that come with the mesh (MTL) join the scene's list under "object/material".
  std::vector<std::uint32_t> material_map;
  if (fixed == UINT32_MAX) {
    for (const MaterialDesc& m : mesh.materials) {
      MaterialDesc copy = m;
      copy.name = (name.empty() ? std::string("mesh") : name) + "/" + m.name;
      material_map.push_back(static_cast<std::uint32_t>(s.materials.size()));
      s.materials.push_back(copy);
    }
  }
  const std::uint32_t dflt = fixed == UINT32_MAX ? DefaultMaterial(s, by_name) : fixed;

  const std::vector<glm::dmat4> transforms = ObjectTransforms(c, oj, f);
  // The limit is checked before the copies are made: a million instances of a mesh must be refused
  // by count, not by running out of memory while placing them.
  std::size_t per_copy = 0;
  for (const SubMesh& sub : mesh.submeshes) per_copy += sub.TriangleCount();
  const double total = static_cast<double>(s.TriangleCount()) + static_cast<double>(per_copy) * static_cast<double>(transforms.size());
  if (total >= static_cast<double>(kMaxSceneTriangles))
    c.Fail(transforms.size() > 1 ? f + ".instances" : f,
           fmt::format("{} placements of {} triangles bring the scene to {:.0f} triangles, beyond the limit of 2^28", transforms.size(),
                       per_copy, total));
  for (std::size_t k = 0; k < transforms.size(); ++k) {
    for (const SubMesh& sub : mesh.submeshes) {
      Object o = PlaceSubMesh(c, f, sub, transforms[k], material_map, fixed, dflt);
      std::string base = name.empty() ? sub.name : (mesh.submeshes.size() == 1 ? name : name + "/" + sub.name);
      o.name = transforms.size() > 1 ? fmt::format("{}#{}", base, k) : base;
      if (o.TriangleCount() > 0) s.objects.push_back(std::move(o));
    }
  }
}

}  // namespace

std::size_t Scene::TriangleCount() const {
  std::size_t n = 0;
  for (const Object& o : objects) n += o.TriangleCount();
  return n;
}

bool Scene::HasAreaLight() const {
  for (const LightDesc& l : lights)
    if (l.IsArea()) return true;
  return false;
}

std::size_t ShadowSlotsPerSurface(const std::vector<LightDesc>& lights) {
  std::size_t n = 0;
  for (const LightDesc& l : lights) n += static_cast<std::size_t>(l.samples);
  return n;
}

Scene LoadScene(const std::filesystem::path& path, const LoadOptions& options) {
  Ctx c{path.string()};
  const json root = ParseFile(path);
  CheckKeys(c, root, "scene", {"name", "camera", "image", "lights", "materials", "objects", "max_depth"});

  Scene s;
  s.path = path;
  s.files.push_back(path);
  s.name = path.stem().string();
  if (root.contains("name")) s.name = String(c, root["name"], "name");
  s.camera = ParseCamera(c, Required(c, root, "camera", ""));
  const json& image = Required(c, root, "image", "");
  CheckKeys(c, image, "image", {"width", "height"});
  s.width = Integer(c, Required(c, image, "width", "image"), "image.width", 1, kMaxImageSide);
  s.height = Integer(c, Required(c, image, "height", "image"), "image.height", 1, kMaxImageSide);
  if (root.contains("max_depth")) s.max_depth = Integer(c, root["max_depth"], "max_depth", 0, kMaxDepth);

  std::map<std::string, std::uint32_t> by_name;
  ParseLightsAndMaterials(c, root, s, by_name);
  const json& objects = Required(c, root, "objects", "");
  if (!objects.is_array() || objects.empty()) c.Fail("objects", "expected a non-empty array");
  for (std::size_t i = 0; i < objects.size(); ++i) AddObject(c, objects[i], i, path.parent_path(), options, s, by_name);
  if (s.TriangleCount() == 0) c.Fail("objects", "the scene has no triangles");
  if (s.TriangleCount() >= kMaxSceneTriangles) c.Fail("objects", "more than 2^28 triangles");
  return s;
}

}  // namespace rayspace
