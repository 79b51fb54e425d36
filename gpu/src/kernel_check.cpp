#include "rayspace/gpu/kernel_check.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <spirv_cross/spirv_cross_c.h>

#include "rayspace/error.h"
#include "rayspace/gpu/passes.h"
#include "rayspace/input_file.h"
#include "rayspace/output_file.h"

namespace rayspace::gpu_backend {
namespace {

// Owns an spvc_context (which owns everything created from it).
struct Spvc {
  spvc_context ctx = nullptr;
  Spvc() { spvc_context_create(&ctx); }
  ~Spvc() {
    if (ctx) spvc_context_destroy(ctx);
  }
  std::string Error() const { return ctx ? spvc_context_get_last_error_string(ctx) : "no context"; }
};

std::string ScalarName(spvc_type t) {
  std::string base;
  switch (spvc_type_get_basetype(t)) {
    case SPVC_BASETYPE_UINT32: base = "uint"; break;
    case SPVC_BASETYPE_INT32: base = "int"; break;
    case SPVC_BASETYPE_FP32: base = "float"; break;
    case SPVC_BASETYPE_UINT64: base = "uint64_t"; break;
    case SPVC_BASETYPE_INT64: base = "int64_t"; break;
    case SPVC_BASETYPE_FP64: base = "double"; break;
    case SPVC_BASETYPE_BOOLEAN: base = "bool"; break;
    default: base = fmt::format("type{}", static_cast<int>(spvc_type_get_basetype(t)));
  }
  const unsigned v = spvc_type_get_vector_size(t), c = spvc_type_get_columns(t);
  if (c > 1) return fmt::format("{}mat{}x{}", base, c, v);
  if (v > 1) return fmt::format("{}vec{}", base, v);
  return base;
}

// Flattens a struct's members (nested structs and arrays included) to scalars/vectors at offsets.
void Flatten(spvc_compiler comp, spvc_type st, std::uint32_t base, std::vector<KernelInterface::Scalar>& out) {
  const unsigned n = spvc_type_get_num_member_types(st);
  for (unsigned i = 0; i < n; ++i) {
    unsigned off = 0;
    spvc_compiler_type_struct_member_offset(comp, st, i, &off);
    const spvc_type mt = spvc_compiler_get_type_handle(comp, spvc_type_get_member_type(st, i));
    if (spvc_type_get_num_array_dimensions(mt) > 0) {
      out.push_back({base + off, ScalarName(mt) + "[]"});
    } else if (spvc_type_get_basetype(mt) == SPVC_BASETYPE_STRUCT) {
      Flatten(comp, mt, base + off, out);
    } else {
      out.push_back({base + off, ScalarName(mt)});
    }
  }
}

std::string Describe(const std::vector<KernelInterface::Scalar>& v) {
  std::string s;
  for (const auto& m : v) s += fmt::format("{}{} at {}", s.empty() ? "" : ", ", m.type, m.offset);
  return s.empty() ? "none" : s;
}

}  // namespace

vk::Status ReflectKernel(std::span<const std::uint32_t> spirv, KernelInterface& out) {
  out = {};
  Spvc s;
  spvc_parsed_ir ir = nullptr;
  spvc_compiler comp = nullptr;
  spvc_resources res = nullptr;
  if (!s.ctx || spvc_context_parse_spirv(s.ctx, spirv.data(), spirv.size(), &ir) != SPVC_SUCCESS)
    return vk::Status::Fail("not valid SPIR-V: " + s.Error());
  if (spvc_context_create_compiler(s.ctx, SPVC_BACKEND_NONE, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP, &comp) != SPVC_SUCCESS ||
      spvc_compiler_create_shader_resources(comp, &res) != SPVC_SUCCESS)
    return vk::Status::Fail("SPIR-V reflection failed: " + s.Error());
  out.compute = spvc_compiler_get_execution_model(comp) == SpvExecutionModelGLCompute;
  auto add = [&](spvc_resource_type type, bool storage) {
    const spvc_reflected_resource* list = nullptr;
    size_t count = 0;
    spvc_resources_get_resource_list_for_type(res, type, &list, &count);
    for (size_t i = 0; i < count; ++i) {
      KernelInterface::Binding b;
      b.set = spvc_compiler_get_decoration(comp, list[i].id, SpvDecorationDescriptorSet);
      b.binding = spvc_compiler_get_decoration(comp, list[i].id, SpvDecorationBinding);
      const char* name = spvc_compiler_get_name(comp, list[i].base_type_id);
      b.name = name && *name ? name : list[i].name;
      b.storage_buffer = storage;
      out.bindings.push_back(b);
    }
  };
  add(SPVC_RESOURCE_TYPE_STORAGE_BUFFER, true);
  for (spvc_resource_type t : {SPVC_RESOURCE_TYPE_UNIFORM_BUFFER, SPVC_RESOURCE_TYPE_STORAGE_IMAGE, SPVC_RESOURCE_TYPE_SAMPLED_IMAGE,
                               SPVC_RESOURCE_TYPE_SEPARATE_IMAGE, SPVC_RESOURCE_TYPE_SEPARATE_SAMPLERS})
    add(t, false);
  std::sort(out.bindings.begin(), out.bindings.end(),
            [](const auto& a, const auto& b) { return a.set != b.set ? a.set < b.set : a.binding < b.binding; });
  const spvc_reflected_resource* pcs = nullptr;
  size_t pc_count = 0;
  spvc_resources_get_resource_list_for_type(res, SPVC_RESOURCE_TYPE_PUSH_CONSTANT, &pcs, &pc_count);
  if (pc_count > 0) {
    const spvc_type t = spvc_compiler_get_type_handle(comp, pcs[0].base_type_id);
    size_t size = 0;
    spvc_compiler_get_declared_struct_size(comp, t, &size);
    out.push_bytes = static_cast<std::uint32_t>(size);
    Flatten(comp, t, 0, out.push);
  }
  spvc_specialization_constant x{}, y{}, z{};
  spvc_compiler_get_work_group_size_specialization_constants(comp, &x, &y, &z);
  const unsigned sy = spvc_compiler_get_execution_mode_argument_by_index(comp, SpvExecutionModeLocalSize, 1);
  const unsigned sz = spvc_compiler_get_execution_mode_argument_by_index(comp, SpvExecutionModeLocalSize, 2);
  out.local_size_from_constant_1 = x.id != 0 && x.constant_id == 1 && y.id == 0 && z.id == 0 && sy <= 1 && sz <= 1;
  return vk::Status::Ok();
}

vk::Status CheckKernel(const PassSpec& pass, std::span<const std::uint32_t> spirv) {
  auto fail = [&](const std::string& what) { return vk::Status::Fail(fmt::format("kernel for pass '{}': {}", pass.name, what)); };
  if (pass.graphics) return fail("the raster is a graphics pipeline; only compute passes take a user kernel");
  KernelInterface user, builtin;
  if (vk::Status st = ReflectKernel(spirv, user); !st) return fail(st.message);
  if (vk::Status st = ReflectKernel(BuiltinKernel(pass.kernel), builtin); !st) return fail("built-in kernel: " + st.message);
  if (!user.compute) return fail("not a compute shader");
  if (!user.local_size_from_constant_1)
    return fail("the workgroup size must be layout(local_size_x_id = 1) in; (the host sets it and counts workgroups by it)");
  for (const KernelInterface::Binding& b : user.bindings) {
    if (!b.storage_buffer) return fail(fmt::format("binding {} ('{}') is not a storage buffer; every binding of the contract is one", b.binding, b.name));
    if (b.set != 0) return fail(fmt::format("binding {} ('{}') is in descriptor set {}; the contract uses set 0", b.binding, b.name, b.set));
    if (b.binding >= pass.bindings)
      return fail(fmt::format("binding {} ('{}') is outside the pass's bindings 0..{} (rayspace/contract.h)", b.binding, b.name,
                              pass.bindings - 1));
    for (const KernelInterface::Binding& c : user.bindings)
      if (&c != &b && c.binding == b.binding && c.set == b.set)
        return fail(fmt::format("binding {} is declared twice ('{}' and '{}')", b.binding, b.name, c.name));
  }
  if (user.push_bytes > pass.push_bytes)
    return fail(fmt::format("push-constant block of {} bytes; the host pushes {} bytes of {}", user.push_bytes, pass.push_bytes,
                            pass.push_type));
  // Every member the user's block declares must sit where the contract's struct has a member of that type.
  for (const KernelInterface::Scalar& m : user.push) {
    bool found = false;
    for (const KernelInterface::Scalar& c : builtin.push) found = found || (c.offset == m.offset && c.type == m.type);
    if (!found)
      return fail(fmt::format("push-constant member {} at byte {} does not match {} ({})", m.type, m.offset, pass.push_type,
                              Describe(builtin.push)));
  }
  return vk::Status::Ok();
}

vk::Status LoadKernelFile(const std::string& path, std::vector<std::uint32_t>& out, const DataPaths& data) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) return vk::Status::Fail(fmt::format("kernel file '{}' not found", path));
  if (const std::string why = NotRegularFile(path); !why.empty())
    return vk::Status::Fail(fmt::format("kernel file '{}' {}", path, why));
  std::string spv_path = path;
  fs::path tmp;
  // The compile's output and log in a directory of its own, removed on every exit and on a signal
  // (TempDirectory), so an interrupted compile leaves nothing under TMPDIR.
  std::optional<TempDirectory> scratch;
  if (fs::path(path).extension() != ".spv") {
    // GLSL: compile as the built-in kernels are compiled (gpu/CMakeLists.txt).
    if (!fs::is_directory(data.shaders, ec) || !fs::is_directory(data.includes / "rayspace", ec))
      return vk::Status::Fail(fmt::format("kernel file '{}': the kernels' GLSL includes are missing from the {} ({} and {})", path,
                                          data.where, data.shaders.string(), (data.includes / "rayspace").string()));
    static std::atomic<unsigned> compiles{0};
    try {
      scratch.emplace(fs::temp_directory_path(ec) / fmt::format("rayspace-kernel-{}-{}", ::getpid(), compiles++));
    } catch (const InputError& e) {
      return vk::Status::Fail(fmt::format("kernel file '{}': no scratch directory to compile it in: {}", path, e.what()));
    }
    tmp = scratch->path() / "kernel.spv";
    const fs::path log = scratch->path() / "glslc.log";
    auto quote = [](const std::string& s) {
      std::string q = "'";
      for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
      return q + "'";
    };
    const std::string dir = fs::absolute(path, ec).parent_path().string();
    const std::string cmd =
        fmt::format("{} -O0 -g --target-env=vulkan1.2 -fshader-stage=compute -I {} -I {} -I {} {} -o {} 2> {}", RAYSPACE_GLSLC,
                    quote(dir), quote(data.shaders.string()), quote(data.includes.string()), quote(path), quote(tmp.string()),
                    quote(log.string()));
    const int rc = std::system(cmd.c_str());
    std::string first;
    {
      std::ifstream in(log);
      std::getline(in, first);
    }
    fs::remove(log, ec);
    if (rc != 0) {
      fs::remove(tmp, ec);
      return vk::Status::Fail(fmt::format("kernel file '{}' does not compile: {}", path, first.empty() ? "glslc failed" : first));
    }
    spv_path = tmp.string();
  }
  std::string bytes;
  try {
    bytes = ReadInputFile(spv_path, {"kernel file", kMaxTextFileBytes});
  } catch (const InputError& e) {
    if (!tmp.empty()) fs::remove(tmp, ec);
    return vk::Status::Fail(e.what());
  }
  if (!tmp.empty()) fs::remove(tmp, ec);
  if (bytes.size() < 20 || bytes.size() % 4 != 0)
    return vk::Status::Fail(fmt::format("kernel file '{}' is not SPIR-V ({} bytes)", path, bytes.size()));
  out.resize(bytes.size() / 4);
  std::memcpy(out.data(), bytes.data(), bytes.size());
  if (out[0] != 0x07230203u) return vk::Status::Fail(fmt::format("kernel file '{}' is not SPIR-V (bad magic number)", path));
  return vk::Status::Ok();
}

}  // namespace rayspace::gpu_backend
