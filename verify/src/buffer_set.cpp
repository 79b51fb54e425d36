#include "rayspace/verify/buffer_set.h"

#include <filesystem>
#include <fstream>

#include "rayspace/input_file.h"
#include "rayspace/json_text.h"
#include "rayspace/output_file.h"

namespace rayspace::verify {
namespace {

constexpr ElemInfo kInfos[] = {
    {"u8", 1, 0},          {"u32", 4, 0},         {"u64", 8, 0},          {"f32", 4, 1},
    {"vec4", 16, 0xF},     {"uvec4", 16, 0},      {"ray", 64, 0xF0FF},    {"surface", 80, 0xFFFF},
    {"cone_node", 48, 0xFFF}, {"triangle", 48, 0xFFF}, {"triangle_normals", 48, 0xFFF}, {"triangle_info", 16, 0},
    {"material", 48, 0xFFF}, {"light", 48, 0xFFF},
    {"frame_constants", 192, 0}};  // 48 words: more than the mask holds; inputs only, never compared
static_assert(sizeof(layout::Ray) == 64 && sizeof(layout::Surface) == 80 && sizeof(layout::ConeNode) == 48);
static_assert(sizeof(layout::FrameConstants) == 192 && sizeof(layout::Material) == 48 && sizeof(layout::Light) == 96);

}  // namespace

const ElemInfo& Info(ElemType t) { return kInfos[static_cast<int>(t)]; }

Blob Blob::FromBytes(ElemType type, std::vector<std::uint8_t>&& bytes) {
  // operator new's alignment (16 bytes) is every element type's.
  auto p = std::make_shared<std::vector<std::uint8_t>>(std::move(bytes));
  Blob b(type, p->data(), p->size());
  b.vector_ = type == ElemType::kU8;
  b.owner_ = std::move(p);
  return b;
}

const Blob& BufferSet::Find(const std::string& name, ElemType type) const {
  auto it = blobs_.find(name);
  if (it == blobs_.end()) ThrowInput("{}: no buffer '{}'", origin_, name);
  if (it->second.type != type)
    ThrowInput("{}: buffer '{}' holds {}, expected {}", origin_, name, Info(it->second.type).name, Info(type).name);
  return it->second;
}

double BufferSet::Scalar(const std::string& name) const {
  if (!scalars.contains(name) || !scalars[name].is_number()) ThrowInput("{}: no numeric scalar '{}'", origin_, name);
  return scalars[name].get<double>();
}

std::uint32_t BufferSet::U32(const std::string& name) const {
  const double v = Scalar(name);
  if (!(v >= 0.0 && v <= 4294967295.0) || v != static_cast<double>(static_cast<std::uint32_t>(v)))
    ThrowInput("{}: scalar '{}' = {} is not a 32-bit unsigned integer", origin_, name, v);
  return static_cast<std::uint32_t>(v);
}

void BufferSet::PutScene(const SceneBuffers& s, bool view) {
  const auto put = [&](const std::string& name, const auto& v) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    if (view) PutView(name, std::span<const T>(v));
    else Put(name, std::span<const T>(v));
  };
  put("scene.triangles", s.triangles);
  put("scene.normals", s.normals);
  put("scene.info", s.info);
  put("scene.materials", s.materials);
  put("scene.lights", s.lights);
  put("scene.objects", s.objects);
  Put("scene.box", std::vector<glm::vec4>{glm::vec4(s.lo, 0.0f), glm::vec4(s.hi, 0.0f)});
}

SceneBuffers BufferSet::GetScene() const {
  SceneBuffers s;
  s.triangles = Get<layout::Triangle>("scene.triangles");
  s.normals = Get<layout::TriangleNormals>("scene.normals");
  s.info = Get<layout::TriangleInfo>("scene.info");
  s.materials = Get<layout::Material>("scene.materials");
  s.lights = Get<layout::Light>("scene.lights");
  s.objects = Get<glm::uvec4>("scene.objects");
  const std::vector<glm::vec4> box = Get<glm::vec4>("scene.box");
  if (box.size() != 2) ThrowInput("{}: buffer 'scene.box' must hold 2 elements", origin_);
  s.lo = glm::vec3(box[0]);
  s.hi = glm::vec3(box[1]);
  const std::size_t n = s.triangles.size();
  if (s.normals.size() != n || s.info.size() != n)
    ThrowInput("{}: scene buffers disagree on the triangle count ({}, {}, {})", origin_, n, s.normals.size(), s.info.size());
  for (std::size_t i = 0; i < n; ++i)
    if (s.info[i].ids.x >= s.materials.size() || s.info[i].ids.y >= s.objects.size())
      ThrowInput("{}: triangle {} names material {} / object {} out of range", origin_, i, s.info[i].ids.x, s.info[i].ids.y);
  return s;
}

void BufferSet::Save(const std::string& dir, const std::string& method) const {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) ThrowInput("{}: cannot create the directory ({})", dir, ec.message());
  nlohmann::json j = {{"method", method}, {"scalars", scalars}, {"buffers", nlohmann::json::object()}};
  // Bulk files: each written whole, none synced. pass.json comes last, so a directory that has it is
  // complete.
  OutputOptions o{"a saved input", false, false, {}};
  for (const auto& [name, b] : blobs_) {
    j["buffers"][name] = {{"type", Info(b.type).name}, {"count", b.count()}};
    OutputFile(dir + "/" + name + ".bin", o).Commit(std::string_view(reinterpret_cast<const char*>(b.bytes().data()), b.bytes().size()));
  }
  OutputFile(dir + "/pass.json", o).Commit(JsonText(j));
}

BufferSet BufferSet::Load(const std::string& dir, std::string& method) {
  namespace fs = std::filesystem;
  const fs::path meta = fs::path(dir) / "pass.json";
  if (std::error_code ec; fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    ThrowInput("{}: not a directory (replay reads a directory written by diff --save-inputs)", dir);
  if (std::error_code ec; !fs::exists(meta, ec))
    ThrowInput("{}: cannot open (is '{}' a directory written by diff --save-inputs?)", meta.string(), dir);
  const std::string text = ReadInputFile(meta, {"pass file", kMaxTextFileBytes});
  nlohmann::json j;
  try {
    j = ParseJson(text);
  } catch (const JsonError& e) {
    ThrowInput("{}: invalid JSON: {}", meta.string(), e.what());
  }
  if (!j.is_object() || !j.contains("method") || !j["method"].is_string() || !j.contains("buffers") ||
      !j["buffers"].is_object())
    ThrowInput("{}: expected an object with 'method' and 'buffers'", meta.string());
  BufferSet s;
  s.origin_ = dir;
  method = j["method"].get<std::string>();
  if (j.contains("scalars") && j["scalars"].is_object()) s.scalars = j["scalars"];
  for (const auto& [name, desc] : j["buffers"].items()) {
    if (name.find('/') != std::string::npos || name.find("..") != std::string::npos)
      ThrowInput("{}: buffer name '{}' is not a plain name", meta.string(), name);
    if (!desc.is_object() || !desc.contains("type") || !desc["type"].is_string() || !desc.contains("count") ||
        !desc["count"].is_number_unsigned())
      ThrowInput("{}: buffer '{}' needs a type and an unsigned count", meta.string(), name);
    int type = -1;
    for (int t = 0; t < static_cast<int>(std::size(kInfos)); ++t)
      if (desc["type"].get<std::string>() == kInfos[t].name) type = t;
    if (type < 0) ThrowInput("{}: buffer '{}' has unknown type '{}'", meta.string(), name, desc["type"].get<std::string>());
    const ElemType elem = static_cast<ElemType>(type);
    const std::uint64_t count = desc["count"].get<std::uint64_t>();
    const fs::path bin = fs::path(dir) / (name + ".bin");
    const std::string bytes = ReadInputFile(bin, {"buffer file", kMaxDataFileBytes});
    const std::uint64_t size = bytes.size();
    // Compared by division: count times the element size may overflow.
    if (size % Info(elem).bytes != 0 || size / Info(elem).bytes != count)
      ThrowInput("{}: {} bytes, expected {} elements of {} bytes", bin.string(), size, count, Info(elem).bytes);
    s.blobs_[name] = Blob::FromBytes(elem, std::vector<std::uint8_t>(bytes.begin(), bytes.end()));
  }
  return s;
}

BufferComparison CompareBlobs(const std::string& pass, const std::string& name, const Blob& expected, const Blob& actual,
                              const std::string& actual_name) {
  RS_CHECK(expected.type == actual.type);
  const ElemInfo& info = Info(expected.type);
  const auto words = [](const Blob& b) {
    return std::span(reinterpret_cast<const std::uint32_t*>(b.bytes().data()), b.bytes().size() / 4);
  };
  BufferComparison c = info.bytes == 1 ? CompareBytes(pass, name, expected.bytes(), actual.bytes())
                                       : CompareWords(pass, name, words(expected), words(actual), info.bytes / 4, info.float_mask);
  c.expected_name = "emu";
  c.actual_name = actual_name;
  return c;
}

}  // namespace rayspace::verify
