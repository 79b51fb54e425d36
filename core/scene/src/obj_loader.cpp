// OBJ + MTL through tinyobjloader. A light pre-pass over the text checks every `v` and `f` line first
// so that a malformed file is reported with its line number (tinyobjloader silently reads bad numbers
// as 0 and does not check index ranges). The OBJ and its MTL files (mtl_reader.h) are read by
// rayspace, not by tinyobjloader, so that only bounded regular files are read (input_file.h).
#include <cmath>
#include <istream>
#include <string_view>

#include <tiny_obj_loader.h>

#include "rayspace/error.h"
#include "rayspace/input_file.h"
#include "rayspace/scene.h"
#include "mtl_reader.h"
#include "obj_text.h"

namespace rayspace {
namespace {

// How many of each element the checked lines define, as face indices refer to them.
struct ObjCounts {
  long long vertices = 0, texcoords = 0, normals = 0;
};

// A `v`, `vn` or `vt` line: at least `need` numbers, of which the first `read` (what the parser
// reads) must be finite as floats. tinyobjloader would read a bad one as 0.
void CheckCoordinates(const std::string& file, std::size_t line_no, const std::vector<std::string_view>& tok,
                      const char* what, std::size_t need, std::size_t read) {
  if (tok.size() < need + 1)
    ThrowInput("{}:{}: {} needs {} coordinate{}", file, line_no, what, need, need == 1 ? "" : "s");
  for (std::size_t k = 1; k <= read && k < tok.size(); ++k) {
    double v;
    if (!obj_text::ParseFloat(tok[k], v)) ThrowInput("{}:{}: bad {} coordinate '{}'", file, line_no, what, tok[k]);
    if (!std::isfinite(v) || std::fabs(v) > 3.0e38)
      ThrowInput("{}:{}: non-finite {} coordinate '{}'", file, line_no, what, tok[k]);
  }
}

void CheckFace(const std::string& file, std::size_t line_no, const std::vector<std::string_view>& tok, const ObjCounts& n) {
  if (tok.size() < 4) ThrowInput("{}:{}: face needs at least 3 vertices", file, line_no);
  const long long counts[3] = {n.vertices, n.texcoords, n.normals};
  const char* names[3] = {"vertex", "texture", "normal"};
  for (std::size_t k = 1; k < tok.size(); ++k) {
    std::string_view t = tok[k];
    for (int part = 0; part < 3 && !t.empty(); ++part) {
      std::size_t slash = t.find('/');
      std::string_view idx = t.substr(0, slash);
      t = slash == std::string_view::npos ? std::string_view{} : t.substr(slash + 1);
      if (idx.empty() && part > 0) continue;  // "1//3"
      long long v;
      if (!obj_text::ParseInt(idx, v) || v == 0) ThrowInput("{}:{}: bad face index '{}'", file, line_no, tok[k]);
      const long long resolved = v < 0 ? counts[part] + v : v - 1;
      if (resolved < 0 || resolved >= counts[part])
        ThrowInput("{}:{}: {} index {} out of range (have {})", file, line_no, names[part], v, counts[part]);
    }
  }
}

// Checks positions, normals, texture coordinates and face indices line by line (text with
// normalised line ends); throws naming file and line.
ObjCounts ValidateObjText(const std::filesystem::path& path, const std::string& text) {
  ObjCounts n;
  const std::string file = path.string();
  obj_text::ForEachLine(text, [&](std::size_t line_no, std::string_view line) {
    const auto tok = obj_text::Tokens(line);
    if (tok.empty()) return;
    if (tok[0] == "v") {
      CheckCoordinates(file, line_no, tok, "vertex", 3, 3);
      ++n.vertices;
    } else if (tok[0] == "vn") {
      CheckCoordinates(file, line_no, tok, "normal", 3, 3);
      ++n.normals;
    } else if (tok[0] == "vt") {
      CheckCoordinates(file, line_no, tok, "texture", 1, 3);
      ++n.texcoords;
    } else if (tok[0] == "f") {
      CheckFace(file, line_no, tok, n);
    }
  });
  return n;
}

// What tinyobjloader makes of the OBJ text, with its warnings and error.
struct ParsedObj {
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
};

std::string OneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text;
}

ParsedObj ParseObj(const std::filesystem::path& path, std::string& text) {
  ParsedObj obj;
  std::string warn, err;
  obj_text::TextBuf buf(text);
  std::istream in(&buf);
  MtlFiles mtl(path);
  // No triangulation: we fan-triangulate ourselves, tinyobjloader may split quads otherwise.
  if (!tinyobj::LoadObj(&obj.attrib, &obj.shapes, &obj.materials, &warn, &err, &in, &mtl, /*triangulate=*/false,
                        /*default_vcols_fallback=*/false)) {
    err = OneLine(err);
    ThrowInput("{}: {}", path.string(), err.empty() ? "cannot parse OBJ" : err);
  }
  if (!warn.empty()) std::fprintf(stderr, "rayspace: warning: %s: %s\n", path.string().c_str(), OneLine(warn).c_str());
  return obj;
}

// What the parser made must be what the checks passed: the same number of vertices, all finite,
// and faces of at least 3 vertices. Should the two ever read a line differently, the mesh is
// refused rather than loaded with what only the parser saw.
void CheckParsed(const std::filesystem::path& path, const ParsedObj& parsed, const ObjCounts& counts) {
  const auto& v = parsed.attrib.vertices;
  if (static_cast<long long>(v.size() / 3) != counts.vertices)
    ThrowInput("{}: the OBJ parser read {} vertices where the file has {} vertex lines", path.string(), v.size() / 3,
               counts.vertices);
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i])) ThrowInput("{}: vertex {} is not finite as parsed", path.string(), i / 3 + 1);
  for (const tinyobj::shape_t& shape : parsed.shapes)
    for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f)
      if (shape.mesh.num_face_vertices[f] < 3)
        ThrowInput("{}: shape '{}' face {} has {} vertices as parsed, a face needs at least 3", path.string(), shape.name,
                   f, int{shape.mesh.num_face_vertices[f]});
}

}  // namespace

MeshData LoadObj(const std::filesystem::path& path) {
  std::string text = ReadInputFile(path, {"mesh", kMaxDataFileBytes, Gzip::kByExtension, true});
  obj_text::NormaliseLineEnds(text, path.string());
  const ObjCounts counts = ValidateObjText(path, text);
  const ParsedObj parsed = ParseObj(path, text);
  CheckParsed(path, parsed, counts);
  const auto& attrib = parsed.attrib;
  MeshData mesh;
  for (const tinyobj::material_t& m : parsed.materials) {
    MaterialDesc d;
    d.name = m.name;
    d.diffuse = {m.diffuse[0], m.diffuse[1], m.diffuse[2]};
    d.specular = {m.specular[0], m.specular[1], m.specular[2]};
    // Shininess is an integer exponent in rayspace (powers by repeated squaring in the kernels);
    // MtlFiles has checked it lies in [0, 4096].
    d.shininess = std::round(m.shininess);
    mesh.materials.push_back(d);
  }

  const std::size_t nv = attrib.vertices.size() / 3, nn = attrib.normals.size() / 3;
  for (const tinyobj::shape_t& shape : parsed.shapes) {
    SubMesh sub;
    sub.name = shape.name.empty() ? StemWithoutGz(path) : shape.name;
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
  // "mesh.obj.gz" is an OBJ: the loaders undo gzip while reading.
  std::string ext = (IsGzipName(path) ? path.stem() : path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") return LoadObj(path);
  if (ext == ".ply") return LoadPly(path);
  ThrowInput("{}: unsupported mesh format '{}' (expected .obj or .ply, or either gzipped: .obj.gz, .ply.gz)",
             path.string(), ext);
}

}  // namespace rayspace
