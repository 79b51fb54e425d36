// The scene model after loading: everything in world space, ready to flatten into GPU buffers.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace rayspace {

struct CameraDesc {
  glm::vec3 eye{0, 0, 1};
  glm::vec3 target{0, 0, 0};
  glm::vec3 up{0, 1, 0};
  float fov_y_deg = 60.0f;
};

enum class LightShape { kPoint, kRect, kDisk, kSphere };

// A light: a point, or an area light of `samples` shadow rays per shading point (docs/area-lights.md).
struct LightDesc {
  glm::vec3 position{0};           // the centre of an area light
  glm::vec3 color{1};
  float intensity = 1.0f;
  glm::vec3 attenuation{1, 0, 0};  // constant, linear, quadratic
  LightShape shape = LightShape::kPoint;
  glm::vec3 normal{0, -1, 0};      // rect and disk: the side the shape faces (unit)
  glm::vec2 size{0};               // rect: width, height
  float radius = 0.0f;             // disk, sphere
  int samples = 1;                 // 1 for a point light; default 8 for an area light
  bool IsArea() const { return shape != LightShape::kPoint; }
};

// Shadow rays per shading point: the sum of the lights' samples.
std::size_t ShadowSlotsPerSurface(const std::vector<LightDesc>& lights);

struct MaterialDesc {
  std::string name;
  glm::vec3 diffuse{0.8f};
  glm::vec3 specular{0.0f};
  float shininess = 0.0f;     // integer exponent
  float reflectivity = 0.0f;  // 0..1
  float transparency = 0.0f;  // 0..1
  float ior = 1.0f;
};

// A sub-mesh: a triangle soup with three positions (and three normals) per triangle.
struct SubMesh {
  std::string name;
  std::vector<glm::vec3> positions;  // 3 per triangle
  std::vector<glm::vec3> normals;    // 3 per triangle, or empty (face normals are used)
  std::vector<int> material;         // per triangle: index into the owning mesh's material list, -1 none
  std::size_t TriangleCount() const { return positions.size() / 3; }
};

struct MeshData {
  std::vector<SubMesh> submeshes;
  std::vector<MaterialDesc> materials;  // from MTL, or generator defaults
};

// A sub-mesh placed in the world with resolved scene-level material indices.
struct Object {
  std::string name;
  std::vector<glm::vec3> positions;  // world space, 3 per triangle
  std::vector<glm::vec3> normals;    // world space, 3 per triangle (face normals filled in if absent)
  std::vector<std::uint32_t> material;  // per triangle, index into Scene::materials
  std::size_t TriangleCount() const { return positions.size() / 3; }
};

struct Scene {
  std::string name;
  std::filesystem::path path;
  std::vector<std::filesystem::path> files;  // every file it was read from: the scene JSON and its meshes
  CameraDesc camera;
  int width = 512;
  int height = 512;
  std::vector<LightDesc> lights;
  std::vector<MaterialDesc> materials;
  bool HasAreaLight() const;
  std::vector<Object> objects;
  int max_depth = 1;
  std::size_t TriangleCount() const;
};

struct LoadOptions {
  std::filesystem::path data_root;  // where mesh paths not found beside the scene are looked up
};

// Largest image side accepted from a scene file or --size.
inline constexpr int kMaxImageSide = 16384;
// The pipeline's numeric domain: world coordinates (vertices, camera, lights) of magnitude at most
// 2^62, so that differences and their cross products stay in float range (docs/numerics.md).
inline constexpr double kMaxCoordinate = 4611686018427387904.0;  // 2^62
inline constexpr int kMaxDepth = 16;
// Triangles of a scene: primitive ids and the hierarchy's triangle indices are 28-bit fields.
inline constexpr std::size_t kMaxSceneTriangles = std::size_t{1} << 28;

// Loads and validates a scene JSON. Throws InputError naming the file and field on bad input.
Scene LoadScene(const std::filesystem::path& path, const LoadOptions& options);

// Mesh loaders. Throw InputError naming the file (and line where known).
MeshData LoadObj(const std::filesystem::path& path);
MeshData LoadPly(const std::filesystem::path& path);
MeshData LoadMesh(const std::filesystem::path& path);  // by extension

}  // namespace rayspace
