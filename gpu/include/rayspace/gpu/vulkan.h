// A small Vulkan compute runtime. Lifecycle: Context::Create picks a device; buffers and kernels are
// created from it; a Recorder records dispatches and submits them once; everything is destroyed
// before the Context. Every call that can fail returns a Status naming the Vulkan call that failed.
#pragma once
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "rayspace/gpu/float_controls.h"

#include "rayspace/sim/coverage.h"
#include "rayspace/sim/device.h"

namespace rayspace::vk {

// The outcome of a call at the Vulkan boundary. A failed Vulkan call carries its VkResult and its
// name as values (callers branch on them); other failures (a limit, a missing memory type, a bad
// kernel file) leave `result` at VK_SUCCESS and `call` empty. `message` is the one line for users.
struct Status {
  bool ok = true;
  VkResult result = VK_SUCCESS;  // what the failed Vulkan call returned
  std::string call;              // the failed Vulkan function, e.g. "vkCreateDevice"
  std::string message;           // "vkCreateDevice failed: VK_ERROR_INITIALIZATION_FAILED (-3)"
  std::string checker;           // the simulated device's checker whose finding this is ("racecheck", ...), or ""
  std::string finding;           // ... and the finding as the simulator gave it (kernel, line, invocations, word)
  // The device cannot run the kernel as asked (a subgroup feature it lacks, a loose operation under
  // --strict-math): the run is refused as bad input, naming it, not failed.
  bool refused = false;
  // The device could not finish the work (a Vulkan call failed, or the simulated GPU stopped outside
  // its checkers: the step limit): no output was judged. Otherwise a failure is the kernel's output
  // breaking its contract (a guard word overwritten, a value out of range): a wrong output.
  bool device_fault = false;
  static Status Ok() { return {}; }
  static Status Refuse(const std::string& msg) { return {false, VK_SUCCESS, {}, msg, {}, {}, true}; }
  // `call` may be the call's whole source text (RS_VK passes it): the name is what precedes '('.
  static Status Fail(const std::string& call, VkResult r);
  static Status Fail(const std::string& msg) { return {false, VK_SUCCESS, {}, msg, {}, {}}; }
  explicit operator bool() const { return ok; }
};

// Returns the status of `expr` when it failed.
#define RS_TRY(expr)                          \
  do {                                        \
    ::rayspace::vk::Status rs_s = (expr);     \
    if (!rs_s) return rs_s;                   \
  } while (0)

// "VK_ERROR_OUT_OF_DEVICE_MEMORY" for the results rayspace may meet, else "VkResult".
const char* ResultName(VkResult r);

class Context;
class MemoryPool;
}  // namespace rayspace::vk
namespace rayspace::sim {
struct Program;
}  // namespace rayspace::sim
namespace rayspace::vk {
// A range of a pooled block of device memory (memory.h).
struct MemoryRange {
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize offset = 0, size = 0;
  void* mapped = nullptr;  // the range's first byte, or null in memory the host cannot see
  std::uint32_t block = 0;
};

// A storage buffer (or a read-back target) in pooled device memory. The host reads and writes it in
// place where its memory is mappable (device-local memory the host can see, or host memory);
// otherwise through a staging buffer and a copy on the queue that is waited for (Context::Stage).
class Buffer {
 public:
  Buffer() = default;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  Buffer(Buffer&& o) noexcept { *this = std::move(o); }
  Buffer& operator=(Buffer&& o) noexcept;
  ~Buffer();
  VkBuffer handle() const { return buffer_; }
  std::size_t size() const { return size_; }
  bool mapped() const { return mapped_ != nullptr; }
  // bytes from src to the buffer's start; the whole buffer zeroed; bytes from its start to dst.
  [[nodiscard]] Status Write(const void* src, std::size_t bytes);
  [[nodiscard]] Status Zero();
  [[nodiscard]] Status Read(void* dst, std::size_t bytes) const;
  template <typename T>
  [[nodiscard]] Status Upload(const std::vector<T>& v) { return Write(v.data(), v.size() * sizeof(T)); }
  template <typename T>
  [[nodiscard]] Status Upload(std::span<const T> v) { return Write(v.data(), v.size_bytes()); }
  template <typename T>
  [[nodiscard]] Status Download(std::size_t count, std::vector<T>& out) const {
    out.resize(count);
    return Read(out.data(), count * sizeof(T));
  }
  // Guard words: a storage buffer the host can map is made kGuardBytes longer than asked, the excess
  // filled with kGuardWord and bound with the rest, so that a kernel writing past an array's end
  // changes it (Recorder::Submit checks every bound buffer) and one reading past it reads kGuardWord
  // rather than robust access's zero, which a comparison then sees.
  static constexpr std::size_t kGuardBytes = 256;
  static constexpr std::uint32_t kGuardWord = 0xA5C3E187u;
  // The first changed guard word and its value, or false (no guard, or intact).
  bool GuardChanged(std::size_t& word, std::uint32_t& value) const;
  // Poison: a new storage buffer the host can map starts filled with kPoisonWord (rayspace/contract.h),
  // not with whatever the memory pool's block last held, so that an element a kernel forgets to write
  // reads back as a value no pass computes and a comparison sees it, rather than passing when reused
  // memory happens to hold the right value.
  static constexpr std::uint32_t kPoisonWord = 0x7FA11A5Eu;  // layout::kPoisonWord (asserted in vulkan.cpp)

 private:
  friend class Context;
  friend class Recorder;  // the simulated device binds and copies the host memory
  Context* ctx_ = nullptr;  // stages the host's reads and writes when the memory is not mapped
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  MemoryPool* pool_ = nullptr;  // the context's; the range goes back to it
  MemoryRange range_{};
  std::size_t size_ = 0, guard_ = 0;
  void* mapped_ = nullptr;
  bool observed_ = false;  // a storage buffer made while an Observer watched (below)
  std::unique_ptr<std::uint8_t[]> host_;  // the simulated device's memory (Context::CreateSimulated)
};

// A compute pipeline over `bindings` storage buffers with up to 128 bytes of push constants and
// two specialization constants: id 0 = planted-fault selector (0 = none), id 1 = local size x.
class Kernel {
 public:
  Kernel() = default;
  Kernel(const Kernel&) = delete;
  Kernel& operator=(const Kernel&) = delete;
  ~Kernel();
  const std::string& name() const { return name_; }
  std::uint32_t local_size() const { return local_size_; }
  std::uint32_t bindings() const { return bindings_; }
  // Launches of at least one workgroup recorded so far: whether the kernel ran at all (a user's
  // kernel the run never launches is not tested by it).
  std::uint64_t launches() const { return launches_; }
  // On the simulated device: the kernel's lines its dispatches so far executed (sim/coverage.h);
  // nothing on a Vulkan device or before its first dispatch.
  std::optional<sim::LineCoverage> coverage() const;

 private:
  friend class Context;
  friend class Recorder;
  VkDevice device_ = VK_NULL_HANDLE;
  std::string name_;
  mutable std::uint64_t launches_ = 0;
  std::uint32_t bindings_ = 0, local_size_ = 64;
  // The module the pipeline was made from: spirv_ with spec_'s branches decided (CreatePipeline).
  mutable VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  // Made at the kernel's first dispatch (Context::CreateKernel says why).
  mutable VkPipeline pipeline_ = VK_NULL_HANDLE;
  std::uint32_t spec_[3] = {};  // common.glsl's specialization constants: kFault, kLocalSize, kStrictMath
  // The simulated device: the module, and its prepared program made at the first dispatch.
  std::vector<std::uint32_t> spirv_;
  // Why the device refuses this kernel at its first dispatch ("" when it does not): the subgroup
  // features its SPIR-V declares and the device lacks.
  std::string refusal_;
  mutable bool strict_checked_ = false;  // --strict-math: no loose operation left (StrictMathRefusal)
  mutable std::shared_ptr<const sim::Program> program_;
  mutable std::vector<std::uint8_t> coverage_;  // per instruction of program_: ran in some dispatch
};

// A 2D image in device memory with one view: a raster target, read back by Recorder::CopyToHost.
class Image {
 public:
  Image() = default;
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;
  Image(Image&& o) noexcept { *this = std::move(o); }
  Image& operator=(Image&& o) noexcept;
  ~Image();
  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }

 private:
  friend class Context;
  friend class Recorder;
  VkDevice device_ = VK_NULL_HANDLE;
  VkImage image_ = VK_NULL_HANDLE;
  MemoryPool* pool_ = nullptr;
  MemoryRange range_{};
  VkImageView view_ = VK_NULL_HANDLE;
  VkImageAspectFlags aspect_ = 0;
  std::uint32_t width_ = 0, height_ = 0;
};

// What Context::CreateGraphics builds: a vertex and a fragment shader over `bindings` storage
// buffers (visible to both stages, no vertex input), drawing triangle lists without culling into
// colour attachments and one depth attachment (LESS test, depth written) over a width x height
// viewport. Every attachment is cleared on load and left in TRANSFER_SRC_OPTIMAL layout for a copy.
struct GraphicsDesc {
  std::string name;  // for error messages
  std::span<const std::uint32_t> vert_spirv, frag_spirv;
  std::uint32_t bindings = 0;
  std::uint32_t fault = 0;                              // fragment specialization constant 0 (0 = none)
  std::span<const VkFormat> colors;                     // colour attachment formats, in location order
  VkFormat depth = VK_FORMAT_D32_SFLOAT;
  std::uint32_t width = 0, height = 0;
  // Planted violations for the validation tests (gpu/tests/validation_test.cpp): the render pass
  // without its subpass dependencies; attachment blend states that differ.
  bool drop_dependencies_for_testing = false;
  bool differing_blend_for_testing = false;
};

// A graphics pipeline with its render pass, made by Context::CreateGraphics.
class Graphics {
 public:
  Graphics() = default;
  Graphics(const Graphics&) = delete;
  Graphics& operator=(const Graphics&) = delete;
  ~Graphics();
  const std::string& name() const { return name_; }

 private:
  friend class Context;
  friend class Recorder;
  VkDevice device_ = VK_NULL_HANDLE;
  std::string name_;
  std::uint32_t bindings_ = 0, attachments_ = 0, width_ = 0, height_ = 0;
  VkShaderModule vert_ = VK_NULL_HANDLE, frag_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkRenderPass pass_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkFramebuffer framebuffer_ = VK_NULL_HANDLE;
};

// What a Context does at the Vulkan boundary, told as it happens, for `rayspace export`, which
// records one pass call and writes it out as a program that needs only the Vulkan loader. Storage
// buffers are told by the Buffer (its handle names it while it lives); staging and read-back buffers
// (storage = false), their copies and the raster's graphics work are not told. Dispatches are told
// when recorded, and the submit of a Recorder that recorded any once it has run.
class Recorder;
class Observer {
 public:
  virtual ~Observer() = default;
  // `spec` holds the specialization constants 0, 1, 2 (planted fault, local size, strict math).
  virtual void KernelCreated(const Kernel& k, std::span<const std::uint32_t> spirv, std::span<const std::uint32_t> spec) = 0;
  virtual void BufferCreated(const Buffer& b) = 0;
  virtual void BufferDestroyed(const Buffer& b) = 0;
  // The host wrote `bytes` from `src` at the buffer's start; src is null for Zero (every byte 0).
  virtual void BufferWritten(const Buffer& b, const void* src, std::size_t bytes) = 0;
  // The host read `bytes` from the buffer's start into `dst` (filled when this is called).
  virtual void BufferRead(const Buffer& b, const void* dst, std::size_t bytes) = 0;
  // A dispatch of gx x gy workgroups (none when either is 0), followed by the Recorder's barrier.
  virtual void Dispatched(const Recorder& r, const Kernel& k, std::span<const Buffer* const> buffers,
                          std::span<const std::uint8_t> push, std::uint32_t gx, std::uint32_t gy) = 0;
  virtual void Submitted(const Recorder& r) = 0;
};

// Records dispatches (with a full memory barrier between them), draws and image read-backs into one
// command buffer.
class Recorder {
 public:
  explicit Recorder(Context& ctx) : ctx_(ctx) {}
  ~Recorder();
  // Dispatches ceil(invocations / local size) groups of `k` over `buffers` with push constants.
  Status Dispatch(const Kernel& k, std::span<const Buffer* const> buffers, const void* push, std::size_t push_size,
                  std::uint32_t invocations);
  // Dispatches `groups` workgroups (kernels that cooperate within a workgroup index it with
  // WorkGroupIndex(), gpu/shaders/workgroup.glsl); wide launches fold into rows as Dispatch's do.
  Status DispatchGroups(const Kernel& k, std::span<const Buffer* const> buffers, const void* push, std::size_t push_size,
                        std::uint64_t groups);
  // Records one render pass of `g` drawing `vertices` vertices over `buffers`, the attachments
  // cleared to `clears` (one per attachment, the depth attachment last).
  Status Draw(const Graphics& g, std::span<const Buffer* const> buffers, std::span<const VkClearValue> clears,
              std::uint32_t vertices);
  // Copies `image` (left by Draw in TRANSFER_SRC_OPTIMAL) into `dst`, readable by the host after Submit.
  Status CopyToHost(const Image& image, const Buffer& dst);
  // Copies the first `bytes` of src to dst, ordered after everything before it and before everything
  // after it, the host's reads included (Context::Stage).
  Status CopyBuffer(const Buffer& src, const Buffer& dst, std::size_t bytes);
  // Submits everything recorded and waits for it.
  Status Submit();

 private:
  Status Begin();
  // A descriptor set of `layout` from the recorder's pools with `buffers` at bindings 0, 1, ...
  // (`kind` and `name` name the pipeline in errors).
  Status BindSet(const char* kind, const std::string& name, VkDescriptorSetLayout layout,
                 std::span<const Buffer* const> buffers, VkDescriptorSet& out);
  Context& ctx_;
  static constexpr std::uint32_t kPoolSets = 128, kPoolDescriptors = 1024;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  std::vector<VkDescriptorPool> pools_;                 // grown on demand, reset after each submit
  std::size_t current_ = static_cast<std::size_t>(-1);  // pool sets are taken from (none yet)
  std::uint32_t sets_left_ = 0, descriptors_left_ = 0;  // room left in pools_[current_]
  bool recording_ = false;
  bool dispatched_ = false;  // a dispatch since the last submit (what an Observer is told of)
  // Each dispatch's kernel and buffers since the last submit, whose guard words Submit checks.
  std::vector<std::pair<std::string, std::vector<const Buffer*>>> bound_;
  // The simulated device: dispatches and copies recorded since the last submit, run by Submit.
  struct SimStep {
    const Kernel* kernel = nullptr;  // null: a copy of `bytes` from src to dst
    std::vector<const Buffer*> buffers;
    std::vector<std::uint8_t> push;
    std::uint32_t gx = 0, gy = 0;
    const Buffer *src = nullptr, *dst = nullptr;
    std::size_t bytes = 0;
  };
  std::vector<SimStep> sim_steps_;
  Status SubmitSimulated();
};

// The instance rayspace uses: Vulkan 1.2, portability enumeration where the loader offers it, and,
// when `messenger` is given and validation is requested (validation.h), the validation layer and its
// messenger.
Status CreateInstance(VkInstance& out, VkDebugUtilsMessengerEXT* messenger);

class Context {
 public:
  // device < 0: the first non-CPU device, else the first CPU device (lavapipe); kSimulatedDevice:
  // CreateSimulated with lavapipe's subgroup size.
  static Status Create(int device, std::unique_ptr<Context>& out, const sim::DeviceConfig& simulated = {});
  // A context whose device is rayspace's simulator (docs/simulator.md): no Vulkan instance or device;
  // buffers live in host memory, kernels run as SPIR-V on the CPU at each submit, and the limits are
  // lavapipe's. Graphics pipelines and images are refused (the raster comes from the emulator).
  static constexpr int kSimulatedDevice = -1000;
  static Status CreateSimulated(const sim::DeviceConfig& config, std::unique_ptr<Context>& out);
  bool simulated() const { return simulated_; }
  // Lane-instructions the simulated device executed so far.
  std::uint64_t simulated_instructions() const { return sim_instructions_; }
  ~Context();
  // A storage buffer is refused beyond storage_limit() (one binding must not exceed it); transfer-only
  // buffers (storage = false, raster read-back) are limited by memory alone.
  // `poison`: fill a mappable storage buffer with Buffer::kPoisonWord; false only for a buffer the
  // caller overwrites whole at once (an upload).
  Status CreateBuffer(std::size_t bytes, Buffer& out, bool storage = true, bool poison = true);
  // Checks the kernel against the device's limits and makes its layouts; its module and pipeline are
  // made at its first dispatch (Recorder::Dispatch), since a frame runs a few of the passes and
  // lavapipe spends up to a tenth of a second on a pipeline even from its shader cache.
  Status CreateKernel(const std::string& name, std::span<const std::uint32_t> spirv, std::uint32_t bindings,
                      std::uint32_t fault, Kernel& out, std::uint32_t local_size = 64);
  // Makes `k`'s pipeline unless it has one, from its SPIR-V with the branches its specialization
  // constants decide removed (sim::WithBranchesDecided; docs/gpu.md says why).
  Status CreatePipeline(const Kernel& k) const;
  // Plants `fault` in `k` (specialization constant 0) in place of its current one: a pipeline made
  // with the old constant is destroyed, and the next dispatch makes one with the new. Only between
  // submissions (no recorded work may use the pipeline), and refused while an Observer watches, which
  // was told the kernel's constants when it was made.
  Status SetKernelFault(Kernel& k, std::uint32_t fault) const;
  // A width x height 2D image of `format` for `usage` (a copy source as well) with a view of `aspect`;
  // each side must be in [1, maxImageDimension2D] (refused before any Vulkan call otherwise).
  Status CreateImage(VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect, std::uint32_t width,
                     std::uint32_t height, Image& out);
  // The pipeline `desc` describes, rendering into `attachments` (the colour images in order, then
  // the depth image), which must outlive it.
  Status CreateGraphics(const GraphicsDesc& desc, std::span<const Image* const> attachments, Graphics& out);
  const std::string& device_name() const { return device_name_; }
  // Invocations per subgroup as the device reports it (kernels read gl_SubgroupSize; the host uses
  // it only to size launches).
  std::uint32_t subgroup_size() const { return subgroup_size_; }
  std::string driver() const { return driver_; }
  // Settings::strict_math (--strict-math): kernels made while it is in force divide and take square
  // roots correctly rounded in integer arithmetic (rayspace/strict_math.h), so they give the
  // emulator's bits on any conformant device.
  static bool StrictMath();
  // Settings::poison_new_buffers: whether new storage buffers are poisoned (Buffer::kPoisonWord); on
  // by default, so that diff, replay and the tests see unwritten words. render and bench, the timed
  // frames, turn it off: filling every new buffer cost their Vulkan frame a sixth of its time and a
  // third more resident memory (docs/gpu.md, "Poison").
  //
  // A context tells Settings::observer (as in force when it is created) what it does; the observer
  // must outlive it.
  Observer* observer() const { return observer_; }
  // lavapipe: its float operations are correctly rounded (docs/gpu.md), so its kernels give the
  // emulator's bits; on other devices Vulkan's looser division and square root may not.
  bool correctly_rounded_floats() const {
    return simulated_ ? sim_config_.arithmetic.model == sim::DeviceModel::kLavapipe : driver_id_ == VK_DRIVER_ID_MESA_LLVMPIPE;
  }
  // shaderFloat64 enabled (with 64-bit SignedZeroInfNanPreserve): the grids' build kernels exist.
  bool float64() const { return float64_; }
  // The most bytes one storage binding may hold: maxStorageBufferRange unless lowered for tests.
  VkDeviceSize storage_limit() const { return storage_limit_; }
  // Test hook: behave like a device with smaller limits (0 leaves a limit as it is), so that the
  // splitting, paging and grid-folding paths run on small frames.
  void LimitForTesting(VkDeviceSize storage_bytes, std::uint32_t groups_x);
  // Descriptor pools the recorders have created so far (a recorder adds one when a pass's parts
  // outgrow the pools it has; for tests).
  std::size_t descriptor_pools_created() const { return descriptor_pools_; }
  // Launches folded into more than one row of workgroups so far (for reports and warnings).
  std::size_t folded_launches() const { return folded_launches_; }
  // vkDeviceMemory objects alive now and at most so far (buffers and images share pooled blocks).
  std::size_t memory_allocations() const;
  // The host's access to a buffer whose memory it cannot map: a host-visible staging buffer and a
  // copy to (`to_device`) or from the buffer, submitted and waited for.
  Status Stage(const Buffer& b, void* host, std::size_t bytes, bool to_device);
  std::size_t peak_memory_allocations() const;
  // Every physical device, for error messages and --device listings.
  static std::vector<std::string> ListDevices();

 private:
  void ReadProperties();
  Status CreateDevice();
  // A new buffer's poison and guard words (where given), told to the observer, moved to `out`.
  Status Finish(Buffer& b, std::size_t guard, bool poison, bool storage, Buffer& out);
  friend class Recorder;
  // Submits one ended command buffer to the queue and waits for it.
  Status SubmitAndWait(VkCommandBuffer cmd);
  // A memory type allowed by `bits` with all of `flags`, or UINT32_MAX.
  std::uint32_t FindMemoryType(std::uint32_t bits, VkMemoryPropertyFlags flags) const;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;  // --validate only
  Observer* observer_ = nullptr;                          // rayspace export only
  std::unique_ptr<MemoryPool> pool_;                      // every buffer's and image's memory
  std::uint32_t max_allocations_ = 4096;                  // maxMemoryAllocationCount
  VkDriverId driver_id_{};
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t family_ = 0;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory_{};
  std::string device_name_, driver_;
  VkDeviceSize max_storage_range_ = 0, storage_limit_ = 0;
  std::uint32_t max_groups_[2] = {65535, 65535};
  bool float64_ = false;
  // The subgroup features the device offers in compute (ComputeSubgroupFeatures): a kernel that
  // declares another is refused at creation, naming it.
  VkSubgroupFeatureFlags subgroup_features_ = 0;
  FloatControls float_controls_;  // requested in every kernel the device offers them for
  std::uint32_t max_stage_storage_buffers_ = 0, max_image_side_ = 0, subgroup_size_ = 1;
  std::uint32_t max_invocations_ = 0, max_size_x_ = 0;  // maxComputeWorkGroupInvocations, ...Size[0]
  std::size_t descriptor_pools_ = 0;
  std::size_t folded_launches_ = 0;
  bool simulated_ = false;
  sim::DeviceConfig sim_config_;
  std::uint64_t sim_instructions_ = 0, sim_dispatches_ = 0;
};

}  // namespace rayspace::vk
