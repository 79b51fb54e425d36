// OBJ + MTL through tinyobjloader. A light pre-pass over the text checks every `v` and `f` line first
// so that a malformed file is reported with its line number (tinyobjloader silently reads bad numbers
// as 0 and does not check index ranges).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string_view>

#include <tiny_obj_loader.h>

#include "rayspace/error.h"
#include "rayspace/scene.h"

namespace rayspace {
namespace {

std::string ReadFile(const std::filesystem::path& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) ThrowInput("{}: cannot open {}", path.string(), what);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::string_view> Tokens(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

bool ParseFloat(std::string_view s, double& v) {
  auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool ParseInt(std::string_view s, long long& v) {
  auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// Checks positions and face indices line by line; throws naming file and line.
void ValidateObjText(const std::filesystem::path& path, const std::string& text) {
  long long vertices = 0, normals = 0, texcoords = 0;
  std::size_t line_no = 0, pos = 0;
  const std::string file = path.string();
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    auto tok = Tokens(line);
    if (tok.empty()) continue;
    if (tok[0] == "v") {
      if (tok.size() < 4) ThrowInput("{}:{}: vertex needs 3 coordinates", file, line_no);
      for (int k = 1; k <= 3; ++k) {
        double v;
        if (!ParseFloat(tok[k], v)) ThrowInput("{}:{}: bad vertex coordinate '{}'", file, line_no, tok[k]);
        if (!std::isfinite(v) || std::fabs(v) > 3.0e38)
          ThrowInput("{}:{}: non-finite vertex coordinate '{}'", file, line_no, tok[k]);
      }
      ++vertices;
    } else if (tok[0] == "vn") {
      ++normals;
    } else if (tok[0] == "vt") {
      ++texcoords;
    } else if (tok[0] == "f") {
      if (tok.size() < 4) ThrowInput("{}:{}: face needs at least 3 vertices", file, line_no);
      for (std::size_t k = 1; k < tok.size(); ++k) {
        std::string_view t = tok[k];
        const long long counts[3] = {vertices, texcoords, normals};
        const char* names[3] = {"vertex", "texture", "normal"};
        for (int part = 0; part < 3 && !t.empty(); ++part) {
          std::size_t slash = t.find('/');
          std::string_view idx = t.substr(0, slash);
          t = slash == std::string_view::npos ? std::string_view{} : t.substr(slash + 1);
          if (idx.empty() && part > 0) continue;  // "1//3"
          long long v;
          if (!ParseInt(idx, v) || v == 0)
            ThrowInput("{}:{}: bad face index '{}'", file, line_no, tok[k]);
          const long long resolved = v < 0 ? counts[part] + v : v - 1;
          if (resolved < 0 || resolved >= counts[part])
            ThrowInput("{}:{}: {} index {} out of range (have {})", file, line_no, names[part], v, counts[part]);
        }
      }
    }
  }
}

}  // namespace

MeshData LoadObj(const std::filesystem::path& path) {
  const std::string text = ReadFile(path, "mesh");
  ValidateObjText(path, text);

  tinyobj::ObjReaderConfig config;
  config.triangulate = false;  // we fan-triangulate ourselves: tinyobjloader may split quads otherwise
  config.vertex_color = false;
  config.mtl_search_path = path.parent_path().string();
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path.string(), config)) {
    std::string err = reader.Error();
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    for (char& c : err) if (c == '\n') c = ' ';
    ThrowInput("{}: {}", path.string(), err.empty() ? "cannot parse OBJ" : err);
  }
  if (!reader.Warning().empty()) {
    std::string w = reader.Warning();
    for (char& c : w) if (c == '\n') c = ' ';
    std::fprintf(stderr, "rayspace: warning: %s: %s\n", path.string().c_str(), w.c_str());
  }

  const auto& attrib = reader.GetAttrib();
  MeshData mesh;
  for (const tinyobj::material_t& m : reader.GetMaterials()) {
    MaterialDesc d;
    d.name = m.name;
    d.diffuse = {m.diffuse[0], m.diffuse[1], m.diffuse[2]};
    d.specular = {m.specular[0], m.specular[1], m.specular[2]};
    // Shininess is an integer exponent in rayspace (powers by repeated squaring in the kernels).
    d.shininess = std::clamp(std::round(m.shininess), 0.0f, 4096.0f);
    mesh.materials.push_back(d);
  }

  const std::size_t nv = attrib.vertices.size() / 3, nn = attrib.normals.size() / 3;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    SubMesh sub;
    sub.name = shape.name.empty() ? path.stem().string() : shape.name;
    const auto& m = shape.mesh;
    bool has_normals = true;
    for (const auto& idx : m.indices)
      if (idx.normal_index < 0) { has_normals = false; break; }
    std::size_t base = 0;
    for (std::size_t f = 0; f < m.num_face_vertices.size(); ++f) {
      const std::size_t count = m.num_face_vertices[f];
      const int material = f < m.material_ids.size() ? m.material_ids[f] : -1;
      auto vertex = [&](std::size_t k) {
        const auto& idx = m.indices[base + k];
        // The pre-pass checks indices against its own vertex count; tinyobjloader may count the
        // vertex lines of a malformed file differently, so its indices are checked again here.
        if (idx.vertex_index < 0 || static_cast<std::size_t>(idx.vertex_index) >= nv)
          ThrowInput("{}: shape '{}' face {} refers to vertex {}, but the file defines {} vertices", path.string(), sub.name,
                     f, idx.vertex_index + 1, nv);
        const float* p = &attrib.vertices[3 * idx.vertex_index];
        sub.positions.emplace_back(p[0], p[1], p[2]);
        if (has_normals) {
          if (static_cast<std::size_t>(idx.normal_index) >= nn)
            ThrowInput("{}: shape '{}' face {} refers to normal {}, but the file defines {} normals", path.string(),
                       sub.name, f, idx.normal_index + 1, nn);
          const float* n = &attrib.normals[3 * idx.normal_index];
          sub.normals.emplace_back(n[0], n[1], n[2]);
        }
      };
      for (std::size_t k = 1; k + 1 < count; ++k) {  // fan: (0, k, k+1)
        vertex(0);
        vertex(k);
        vertex(k + 1);
        sub.material.push_back(material >= 0 && static_cast<std::size_t>(material) < mesh.materials.size() ? material : -1);
      }
      base += count;
    }
    if (!sub.positions.empty()) mesh.submeshes.push_back(std::move(sub));
  }
  if (mesh.submeshes.empty()) ThrowInput("{}: no faces", path.string());
  return mesh;
}

MeshData LoadMesh(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") return LoadObj(path);
  if (ext == ".ply") return LoadPly(path);
  ThrowInput("{}: unsupported mesh format '{}' (expected .obj or .ply)", path.string(), ext);
}

}  // namespace rayspace
