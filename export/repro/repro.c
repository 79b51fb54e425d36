/* A standalone reproducer of one rayspace pass call on a Vulkan device (written by `rayspace export`).
 *
 *   cc repro.c -lvulkan -o repro
 *   ./repro [DIR] [--device N] [--validate]
 *
 * It replays DIR/sequence.txt (DIR defaults to the current directory) with nothing but the Vulkan
 * loader: the compute pipelines (SPIR-V files and their specialization constants), the storage
 * buffers with what the host wrote into them, every dispatch with its push constants, workgroup
 * counts and bindings, followed by a memory barrier as in rayspace, the submits, and the host's
 * read-backs, each compared bit for bit with the expected bytes. Every buffer starts zeroed.
 *
 * --device N picks the N-th device the loader lists; without it, the first with a compute queue and
 * Vulkan 1.2. --validate (or REPRO_VALIDATE=1) enables VK_LAYER_KHRONOS_validation with
 * synchronization validation; every warning or error it reports is printed and counted.
 *
 * Exit codes: 0 every read-back equal; 1 a read-back differs (the first difference is printed);
 * 2 bad arguments or export files; 3 no usable device or a Vulkan call failed; 4 the validation
 * layer reported a message.
 *
 * sequence.txt: one step per line, '#' starts a comment; the first line is "rayspace-repro 1".
 *   pipeline ID PASS SPIRV_FILE BINDINGS FAULT LOCAL_SIZE STRICT_MATH
 *       a compute pipeline over BINDINGS storage buffers (set 0, bindings 0..BINDINGS-1), 128 bytes of
 *       push constants, specialization constants 0 = FAULT, 1 = LOCAL_SIZE, 2 = STRICT_MATH
 *   buffer ID BYTES LABEL      a storage buffer of BYTES bytes (at least 16 are allocated), zeroed
 *   write ID FILE BYTES        the host writes FILE (BYTES bytes) at the buffer's start
 *   zero ID                    the host zeroes the buffer
 *   dispatch PIPELINE GX GY PUSH_BYTES PUSH_WORD... BUFFER...
 *       records a dispatch of GX x GY x 1 workgroups (none when one is 0) with PUSH_BYTES of push
 *       constants (PUSH_BYTES / 4 words in hexadecimal) and the buffers bound whole at bindings
 *       0, 1, ..., then a barrier from compute writes to compute, transfer and host accesses
 *   submit                     submits the recorded dispatches and waits for them
 *   read ID BYTES FILE OUTPUT OFFSET ELEMENT_BYTES
 *       the host reads BYTES bytes from the buffer's start, which must equal FILE; OUTPUT names the
 *       pass output they land in at byte OFFSET (elements of ELEMENT_BYTES), or is '-' for an
 *       intermediate read-back (one the host merges or converts into the outputs, or a count or
 *       block sums that size what it does next)
 *   free ID                    the buffer is destroyed
 */
#include <inttypes.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <vulkan/vulkan.h>

enum { kExitEqual = 0, kExitMismatch = 1, kExitUsage = 2, kExitVulkan = 3, kExitValidation = 4 };
enum { kMaxTokens = 160, kPushBytes = 128, kNameBytes = 96 };

typedef struct {
  VkBuffer buffer;
  VkDeviceMemory memory;
  unsigned char* mapped;
  uint64_t bytes;
  char label[kNameBytes];
  int live;
} Buf;

typedef struct {
  VkShaderModule module;
  VkDescriptorSetLayout set_layout;
  VkPipelineLayout layout;
  VkPipeline pipeline;
  uint32_t bindings;
  char pass[kNameBytes];
} Pipe;

typedef struct {
  const char* dir;
  int device_index; /* -1: the first usable */
  int validate;
  VkInstance instance;
  VkDebugUtilsMessengerEXT messenger;
  VkPhysicalDevice physical;
  VkPhysicalDeviceProperties props;
  VkPhysicalDeviceMemoryProperties memory;
  VkDevice device;
  VkQueue queue;
  uint32_t family;
  VkCommandPool command_pool;
  VkCommandBuffer cmd;
  int recording;
  VkDescriptorPool* pools; /* one per dispatch of the current submit */
  size_t pool_count, pool_capacity;
  Pipe* pipes;
  size_t pipe_count;
  Buf* bufs;
  size_t buf_count;
  int line; /* of sequence.txt, for messages */
  unsigned long reads, reads_differing;
  unsigned long long words, words_differing;
} Repro;

static unsigned long g_validation_messages = 0;

static void Die(int code, const char* fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fputs("repro: ", stderr);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
  va_end(ap);
  exit(code);
}

/* A failed Vulkan call: its name (the text before '(') and its VkResult. */
static void Check(VkResult result, const char* call) {
  size_t n = strcspn(call, "(");
  if (result != VK_SUCCESS) Die(kExitVulkan, "%.*s failed: VkResult %d", (int)n, call, (int)result);
}
#define VK(call) Check((call), #call)

static void* Grow(void* array, size_t count, size_t* capacity, size_t size) {
  if (count < *capacity) return array;
  *capacity = *capacity ? *capacity * 2 : 16;
  array = realloc(array, *capacity * size);
  if (!array) Die(kExitVulkan, "out of host memory");
  return array;
}

/* ---- the export's files ------------------------------------------------------------------------ */

static void PathOf(const Repro* r, const char* file, char* out, size_t size) {
  if (file[0] == '/' || strstr(file, "..")) Die(kExitUsage, "sequence.txt:%d: '%s' is not a file of the export", r->line, file);
  if (snprintf(out, size, "%s/%s", r->dir, file) >= (int)size) Die(kExitUsage, "sequence.txt:%d: path too long", r->line);
}

/* The whole of `file` in the export; *bytes receives its size, which must be `expect` unless that is -1. */
static unsigned char* ReadFile(const Repro* r, const char* file, long expect, long* bytes) {
  char path[4096];
  PathOf(r, file, path, sizeof path);
  FILE* f = fopen(path, "rb");
  if (!f) Die(kExitUsage, "%s: cannot open", path);
  if (fseek(f, 0, SEEK_END) != 0) Die(kExitUsage, "%s: cannot seek", path);
  long size = ftell(f);
  if (size < 0 || fseek(f, 0, SEEK_SET) != 0) Die(kExitUsage, "%s: cannot tell its size", path);
  if (expect >= 0 && size != expect) Die(kExitUsage, "%s: %ld bytes, sequence.txt:%d expects %ld", path, size, r->line, expect);
  unsigned char* data = malloc(size ? (size_t)size : 1);
  if (!data) Die(kExitVulkan, "out of host memory");
  if (size && fread(data, 1, (size_t)size, f) != (size_t)size) Die(kExitUsage, "%s: cannot read", path);
  fclose(f);
  *bytes = size;
  return data;
}

static uint64_t Number(const Repro* r, const char* token, uint64_t max, const char* what) {
  char* end = NULL;
  unsigned long long v = token ? strtoull(token, &end, 10) : 0;
  if (!token || !*token || *end || token[0] == '-' || v > max)
    Die(kExitUsage, "sequence.txt:%d: %s '%s' is not a number in [0, %" PRIu64 "]", r->line, what, token ? token : "", max);
  return (uint64_t)v;
}

static uint32_t HexWord(const Repro* r, const char* token) {
  char* end = NULL;
  unsigned long v = token ? strtoul(token, &end, 16) : 0;
  if (!token || !*token || *end || v > 0xffffffffUL) Die(kExitUsage, "sequence.txt:%d: push word '%s' is not 32-bit hexadecimal", r->line, token ? token : "");
  return (uint32_t)v;
}

/* Splits `line` at blanks, up to a '#'; returns the number of tokens, or -1 beyond kMaxTokens. */
static int Tokens(char* line, char** tokens) {
  char* hash = strchr(line, '#');
  if (hash) *hash = '\0';
  int n = 0;
  for (char* p = line;;) {
    while (*p == ' ' || *p == '\t' || *p == '\r') *p++ = '\0';
    if (!*p) return n;
    if (n == kMaxTokens) return -1;
    tokens[n++] = p;
    while (*p && *p != ' ' && *p != '\t' && *p != '\r') ++p;
  }
}

/* ---- instance, device, validation ------------------------------------------------------------- */

static VKAPI_ATTR VkBool32 VKAPI_CALL OnMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                               VkDebugUtilsMessageTypeFlagsEXT type,
                                               const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  (void)severity;
  (void)type;
  (void)user;
  ++g_validation_messages;
  fprintf(stderr, "validation: %s\n", data && data->pMessage ? data->pMessage : "(no text)");
  return VK_FALSE;
}

static void FillMessenger(VkDebugUtilsMessengerCreateInfoEXT* m) {
  memset(m, 0, sizeof *m);
  m->sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
  m->messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  m->messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
  m->pfnUserCallback = OnMessage;
}

static int HasLayer(const char* name) {
  uint32_t n = 0;
  VK(vkEnumerateInstanceLayerProperties(&n, NULL));
  VkLayerProperties* layers = calloc(n ? n : 1, sizeof *layers);
  if (!layers) Die(kExitVulkan, "out of host memory");
  VK(vkEnumerateInstanceLayerProperties(&n, layers));
  int found = 0;
  for (uint32_t i = 0; i < n; ++i) found |= strcmp(layers[i].layerName, name) == 0;
  free(layers);
  return found;
}

static int HasInstanceExtension(const char* name) {
  uint32_t n = 0;
  VK(vkEnumerateInstanceExtensionProperties(NULL, &n, NULL));
  VkExtensionProperties* ext = calloc(n ? n : 1, sizeof *ext);
  if (!ext) Die(kExitVulkan, "out of host memory");
  VK(vkEnumerateInstanceExtensionProperties(NULL, &n, ext));
  int found = 0;
  for (uint32_t i = 0; i < n; ++i) found |= strcmp(ext[i].extensionName, name) == 0;
  free(ext);
  return found;
}

/* Vulkan 1.2; portability enumeration where the loader offers it; with --validate the layer, its
 * synchronization validation and a messenger that also sees instance creation. */
static void CreateInstance(Repro* r) {
  static const char* kLayer = "VK_LAYER_KHRONOS_validation";
  const char* extensions[2];
  uint32_t extension_count = 0;
  VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "rayspace-repro";
  app.apiVersion = VK_API_VERSION_1_2;
  VkInstanceCreateInfo ici = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
#ifdef VK_KHR_portability_enumeration
  if (HasInstanceExtension(VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME)) {
    extensions[extension_count++] = VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME;
    ici.flags |= VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR;
  }
#endif
  VkDebugUtilsMessengerCreateInfoEXT messenger;
  VkValidationFeatureEnableEXT enables[1] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features = {.sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  if (r->validate) {
    if (!HasLayer(kLayer)) Die(kExitVulkan, "--validate: the layer %s is not installed (Debian: vulkan-validationlayers)", kLayer);
    FillMessenger(&messenger);
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;
    features.pNext = &messenger;
    ici.pNext = &features;
    ici.enabledLayerCount = 1;
    ici.ppEnabledLayerNames = &kLayer;
    extensions[extension_count++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
  }
  ici.enabledExtensionCount = extension_count;
  ici.ppEnabledExtensionNames = extension_count ? extensions : NULL;
  VK(vkCreateInstance(&ici, NULL, &r->instance));
  if (r->validate) {
    PFN_vkCreateDebugUtilsMessengerEXT create =
        (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(r->instance, "vkCreateDebugUtilsMessengerEXT");
    if (!create) Die(kExitVulkan, "--validate: vkCreateDebugUtilsMessengerEXT is not available");
    FillMessenger(&messenger);
    VK(create(r->instance, &messenger, NULL, &r->messenger));
  }
}

/* The first queue family with compute, or UINT32_MAX. */
static uint32_t ComputeFamily(VkPhysicalDevice d) {
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(d, &n, NULL);
  VkQueueFamilyProperties* f = calloc(n ? n : 1, sizeof *f);
  if (!f) Die(kExitVulkan, "out of host memory");
  vkGetPhysicalDeviceQueueFamilyProperties(d, &n, f);
  uint32_t family = UINT32_MAX;
  for (uint32_t i = 0; i < n && family == UINT32_MAX; ++i)
    if (f[i].queueFlags & VK_QUEUE_COMPUTE_BIT) family = i;
  free(f);
  return family;
}

static void PickDevice(Repro* r) {
  uint32_t n = 0;
  VK(vkEnumeratePhysicalDevices(r->instance, &n, NULL));
  if (n == 0) Die(kExitVulkan, "no Vulkan device found");
  VkPhysicalDevice* devices = calloc(n, sizeof *devices);
  if (!devices) Die(kExitVulkan, "out of host memory");
  VK(vkEnumeratePhysicalDevices(r->instance, &n, devices));
  if (r->device_index >= (int)n) Die(kExitUsage, "--device %d: only %u Vulkan device(s)", r->device_index, n);
  int chosen = -1;
  for (uint32_t i = 0; i < n && chosen < 0; ++i) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(devices[i], &p);
    const int wanted = r->device_index < 0 ? p.apiVersion >= VK_API_VERSION_1_2 : (int)i == r->device_index;
    if (wanted && ComputeFamily(devices[i]) != UINT32_MAX) chosen = (int)i;
    else if (wanted && r->device_index >= 0) Die(kExitVulkan, "--device %d ('%s') has no compute queue", r->device_index, p.deviceName);
  }
  if (chosen < 0) Die(kExitVulkan, "no Vulkan 1.2 device with a compute queue");
  r->physical = devices[chosen];
  r->family = ComputeFamily(r->physical);
  free(devices);
  vkGetPhysicalDeviceProperties(r->physical, &r->props);
  vkGetPhysicalDeviceMemoryProperties(r->physical, &r->memory);
  if (r->props.apiVersion < VK_API_VERSION_1_2)
    Die(kExitVulkan, "device %d ('%s') supports Vulkan %u.%u; the kernels need 1.2", chosen, r->props.deviceName,
        VK_VERSION_MAJOR(r->props.apiVersion), VK_VERSION_MINOR(r->props.apiVersion));
  printf("device %d: %s (Vulkan %u.%u.%u)\n", chosen, r->props.deviceName, VK_VERSION_MAJOR(r->props.apiVersion),
         VK_VERSION_MINOR(r->props.apiVersion), VK_VERSION_PATCH(r->props.apiVersion));
}

/* One compute queue; the features rayspace enables (64-bit integers and 64-bit buffer atomics, which
 * the final tests and the shading use), each where the device has it. */
static void CreateDevice(Repro* r) {
  VkPhysicalDeviceVulkan12Features has12 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceFeatures2 has = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  has.pNext = &has12;
  vkGetPhysicalDeviceFeatures2(r->physical, &has);
  VkPhysicalDeviceVulkan12Features want12 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  want12.shaderBufferInt64Atomics = has12.shaderBufferInt64Atomics;
  VkPhysicalDeviceFeatures want;
  memset(&want, 0, sizeof want);
  want.shaderInt64 = has.features.shaderInt64;
  want.shaderFloat64 = has.features.shaderFloat64;  /* the grids' build bins in double */
  if (!want.shaderInt64 || !want12.shaderBufferInt64Atomics)
    printf("note: the device lacks shaderInt64 or shaderBufferInt64Atomics; kernels that use them will fail\n");
  if (!want.shaderFloat64) printf("note: the device lacks shaderFloat64; the grid build kernels will fail\n");
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qci = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = r->family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  dci.pNext = &want12;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  dci.pEnabledFeatures = &want;
  VK(vkCreateDevice(r->physical, &dci, NULL, &r->device));
  vkGetDeviceQueue(r->device, r->family, 0, &r->queue);
  VkCommandPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.queueFamilyIndex = r->family;
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  VK(vkCreateCommandPool(r->device, &pci, NULL, &r->command_pool));
  VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = r->command_pool;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VK(vkAllocateCommandBuffers(r->device, &ai, &r->cmd));
}

/* ---- pipelines and buffers ---------------------------------------------------------------------- */

static Pipe* PipeOf(const Repro* r, const char* token) {
  const uint64_t id = Number(r, token, UINT32_MAX, "pipeline id");
  if (id >= r->pipe_count || !r->pipes[id].pipeline) Die(kExitUsage, "sequence.txt:%d: no pipeline %s", r->line, token);
  return &r->pipes[id];
}

static Buf* BufOf(const Repro* r, const char* token) {
  const uint64_t id = Number(r, token, UINT32_MAX, "buffer id");
  if (id >= r->buf_count || !r->bufs[id].live) Die(kExitUsage, "sequence.txt:%d: no buffer %s", r->line, token);
  return &r->bufs[id];
}

static void Layouts(Repro* r, Pipe* p) {
  VkDescriptorSetLayoutBinding* b = calloc(p->bindings ? p->bindings : 1, sizeof *b);
  if (!b) Die(kExitVulkan, "out of host memory");
  for (uint32_t i = 0; i < p->bindings; ++i) {
    b[i].binding = i;
    b[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    b[i].descriptorCount = 1;
    b[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo dl = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  dl.bindingCount = p->bindings;
  dl.pBindings = b;
  VK(vkCreateDescriptorSetLayout(r->device, &dl, NULL, &p->set_layout));
  free(b);
  VkPushConstantRange range = {VK_SHADER_STAGE_COMPUTE_BIT, 0, kPushBytes};
  VkPipelineLayoutCreateInfo pl = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pl.setLayoutCount = 1;
  pl.pSetLayouts = &p->set_layout;
  pl.pushConstantRangeCount = 1;
  pl.pPushConstantRanges = &range;
  VK(vkCreatePipelineLayout(r->device, &pl, NULL, &p->layout));
}

/* pipeline ID PASS SPIRV_FILE BINDINGS FAULT LOCAL_SIZE STRICT_MATH */
static void StepPipeline(Repro* r, char** t, int n) {
  if (n != 8) Die(kExitUsage, "sequence.txt:%d: pipeline takes 7 fields", r->line);
  const uint64_t id = Number(r, t[1], 4095, "pipeline id");
  if (id >= r->pipe_count) {
    Pipe* grown = realloc(r->pipes, (size_t)(id + 1) * sizeof *grown);
    if (!grown) Die(kExitVulkan, "out of host memory");
    memset(grown + r->pipe_count, 0, (size_t)(id + 1 - r->pipe_count) * sizeof *grown);
    r->pipes = grown;
    r->pipe_count = (size_t)id + 1;
  }
  Pipe* p = &r->pipes[id];
  if (p->pipeline) Die(kExitUsage, "sequence.txt:%d: pipeline %s is made twice", r->line, t[1]);
  snprintf(p->pass, sizeof p->pass, "%s", t[2]);
  p->bindings = (uint32_t)Number(r, t[4], 64, "binding count");
  const uint32_t spec[3] = {(uint32_t)Number(r, t[5], UINT32_MAX, "fault"), (uint32_t)Number(r, t[6], 65536, "local size"),
                            (uint32_t)Number(r, t[7], 1, "strict math")};
  long bytes = 0;
  unsigned char* code = ReadFile(r, t[3], -1, &bytes);
  if (bytes == 0 || bytes % 4) Die(kExitUsage, "%s/%s: %ld bytes is not SPIR-V", r->dir, t[3], bytes);
  VkShaderModuleCreateInfo smci = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  smci.codeSize = (size_t)bytes;
  smci.pCode = (const uint32_t*)code;
  VK(vkCreateShaderModule(r->device, &smci, NULL, &p->module));
  free(code);
  Layouts(r, p);
  const VkSpecializationMapEntry entries[3] = {{0, 0, 4}, {1, 4, 4}, {2, 8, 4}};
  const VkSpecializationInfo si = {3, entries, sizeof spec, spec};
  VkComputePipelineCreateInfo cp = {.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  cp.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  cp.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  cp.stage.module = p->module;
  cp.stage.pName = "main";
  cp.stage.pSpecializationInfo = &si;
  cp.layout = p->layout;
  VK(vkCreateComputePipelines(r->device, VK_NULL_HANDLE, 1, &cp, NULL, &p->pipeline));
}

/* Host-visible, coherent memory; device-local too where the device has such a type. */
static uint32_t MemoryType(const Repro* r, uint32_t bits) {
  const VkMemoryPropertyFlags host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  for (int pass = 0; pass < 2; ++pass) {
    const VkMemoryPropertyFlags want = pass == 0 ? host | VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT : host;
    for (uint32_t i = 0; i < r->memory.memoryTypeCount; ++i)
      if ((bits & (1u << i)) && (r->memory.memoryTypes[i].propertyFlags & want) == want) return i;
  }
  Die(kExitVulkan, "no host-visible coherent memory for a storage buffer");
  return 0;
}

/* buffer ID BYTES LABEL */
static void StepBuffer(Repro* r, char** t, int n) {
  if (n != 4) Die(kExitUsage, "sequence.txt:%d: buffer takes 3 fields", r->line);
  const uint64_t id = Number(r, t[1], 1u << 24, "buffer id");
  while (id >= r->buf_count) {
    size_t capacity = r->buf_count;
    r->bufs = Grow(r->bufs, r->buf_count, &capacity, sizeof *r->bufs);
    memset(r->bufs + r->buf_count, 0, (capacity - r->buf_count) * sizeof *r->bufs);
    r->buf_count = capacity;
  }
  Buf* b = &r->bufs[id];
  if (b->live) Die(kExitUsage, "sequence.txt:%d: buffer %s is made twice", r->line, t[1]);
  b->bytes = Number(r, t[2], (uint64_t)1 << 40, "buffer size");
  snprintf(b->label, sizeof b->label, "%s", t[3]);
  VkBufferCreateInfo bci = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bci.size = b->bytes < 16 ? 16 : b->bytes;
  bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  VK(vkCreateBuffer(r->device, &bci, NULL, &b->buffer));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(r->device, b->buffer, &req);
  VkMemoryAllocateInfo mai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = MemoryType(r, req.memoryTypeBits);
  VK(vkAllocateMemory(r->device, &mai, NULL, &b->memory));
  VK(vkBindBufferMemory(r->device, b->buffer, b->memory, 0));
  void* mapped = NULL;
  VK(vkMapMemory(r->device, b->memory, 0, VK_WHOLE_SIZE, 0, &mapped));
  b->mapped = mapped;
  memset(b->mapped, 0, (size_t)bci.size);
  b->live = 1;
}

static void FreeBuf(Repro* r, Buf* b) {
  vkDestroyBuffer(r->device, b->buffer, NULL);
  vkFreeMemory(r->device, b->memory, NULL);  /* unmaps */
  b->live = 0;
}

/* write ID FILE BYTES, zero ID, free ID */
static void StepHost(Repro* r, char** t, int n) {
  if (strcmp(t[0], "write") == 0) {
    if (n != 4) Die(kExitUsage, "sequence.txt:%d: write takes 3 fields", r->line);
    Buf* b = BufOf(r, t[1]);
    const uint64_t bytes = Number(r, t[3], b->bytes, "write size");
    long got = 0;
    unsigned char* data = ReadFile(r, t[2], (long)bytes, &got);
    memcpy(b->mapped, data, (size_t)bytes);
    free(data);
  } else {
    if (n != 2) Die(kExitUsage, "sequence.txt:%d: %s takes 1 field", r->line, t[0]);
    Buf* b = BufOf(r, t[1]);
    if (strcmp(t[0], "zero") == 0) memset(b->mapped, 0, (size_t)b->bytes);
    else FreeBuf(r, b);
  }
}

/* ---- dispatches and submits --------------------------------------------------------------------- */

/* A descriptor set with `count` buffers bound whole, from a pool of its own (destroyed after the submit). */
static VkDescriptorSet BindSet(Repro* r, const Pipe* p, Buf** bufs, uint32_t count) {
  VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, count ? count : 1};
  VkDescriptorPoolCreateInfo dp = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  dp.maxSets = 1;
  dp.poolSizeCount = 1;
  dp.pPoolSizes = &size;
  r->pools = Grow(r->pools, r->pool_count, &r->pool_capacity, sizeof *r->pools);
  VK(vkCreateDescriptorPool(r->device, &dp, NULL, &r->pools[r->pool_count]));
  VkDescriptorSetAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = r->pools[r->pool_count++];
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &p->set_layout;
  VkDescriptorSet set;
  VK(vkAllocateDescriptorSets(r->device, &ai, &set));
  for (uint32_t i = 0; i < count; ++i) {
    const uint64_t range = bufs[i]->bytes < 16 ? 16 : bufs[i]->bytes;
    if (range > r->props.limits.maxStorageBufferRange)
      Die(kExitVulkan, "sequence.txt:%d: buffer '%s' (%" PRIu64 " bytes) exceeds maxStorageBufferRange %u of this device; "
          "export again with --split-bytes %u", r->line, bufs[i]->label, range, r->props.limits.maxStorageBufferRange,
          r->props.limits.maxStorageBufferRange);
    VkDescriptorBufferInfo info = {bufs[i]->buffer, 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet w = {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set;
    w.dstBinding = i;
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    w.pBufferInfo = &info;
    vkUpdateDescriptorSets(r->device, 1, &w, 0, NULL);
  }
  return set;
}

static void CheckGroups(const Repro* r, uint64_t gx, uint64_t gy) {
  const uint32_t* max = r->props.limits.maxComputeWorkGroupCount;
  if (gx > max[0] || gy > max[1])
    Die(kExitVulkan, "sequence.txt:%d: %" PRIu64 " x %" PRIu64 " workgroups exceed maxComputeWorkGroupCount %u x %u of this "
        "device; export again with --max-groups %u", r->line, gx, gy, max[0], max[1], max[0]);
}

/* dispatch PIPELINE GX GY PUSH_BYTES PUSH_WORD... BUFFER... */
static void StepDispatch(Repro* r, char** t, int n) {
  if (n < 5) Die(kExitUsage, "sequence.txt:%d: dispatch takes at least 4 fields", r->line);
  const Pipe* p = PipeOf(r, t[1]);
  const uint64_t gx = Number(r, t[2], UINT32_MAX, "workgroup count"), gy = Number(r, t[3], UINT32_MAX, "workgroup count");
  const uint64_t push_bytes = Number(r, t[4], kPushBytes, "push-constant size");
  const int words = (int)(push_bytes + 3) / 4;
  if (push_bytes % 4 || n != 5 + words + (int)p->bindings)
    Die(kExitUsage, "sequence.txt:%d: dispatch of '%s' needs %d push words and %u buffers", r->line, p->pass, words, p->bindings);
  uint32_t push[kPushBytes / 4];
  for (int i = 0; i < words; ++i) push[i] = HexWord(r, t[5 + i]);
  Buf* bufs[kMaxTokens];
  for (uint32_t i = 0; i < p->bindings; ++i) bufs[i] = BufOf(r, t[5 + words + (int)i]);
  CheckGroups(r, gx, gy);
  if (!r->recording) {
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK(vkBeginCommandBuffer(r->cmd, &bi));
    r->recording = 1;
  }
  VkDescriptorSet set = BindSet(r, p, bufs, p->bindings);
  vkCmdBindPipeline(r->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipeline);
  vkCmdBindDescriptorSets(r->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout, 0, 1, &set, 0, NULL);
  if (push_bytes) vkCmdPushConstants(r->cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, (uint32_t)push_bytes, push);
  if (gx && gy) vkCmdDispatch(r->cmd, (uint32_t)gx, (uint32_t)gy, 1);
  VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
  vkCmdPipelineBarrier(r->cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1,
                       &mb, 0, NULL, 0, NULL);
}

static void StepSubmit(Repro* r) {
  if (!r->recording) return;
  VK(vkEndCommandBuffer(r->cmd));
  r->recording = 0;
  VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &r->cmd;
  VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence;
  VK(vkCreateFence(r->device, &fci, NULL, &fence));
  VK(vkQueueSubmit(r->queue, 1, &si, fence));
  VK(vkWaitForFences(r->device, 1, &fence, VK_TRUE, UINT64_MAX));
  vkDestroyFence(r->device, fence, NULL);
  VK(vkResetCommandBuffer(r->cmd, 0));
  for (size_t i = 0; i < r->pool_count; ++i) vkDestroyDescriptorPool(r->device, r->pools[i], NULL);
  r->pool_count = 0;
}

/* ---- read-backs ------------------------------------------------------------------------------------ */

static uint32_t WordAt(const unsigned char* p, uint64_t at, uint64_t bytes) {
  unsigned char w[4] = {0, 0, 0, 0};
  memcpy(w, p + at, (size_t)(bytes - at < 4 ? bytes - at : 4));
  return (uint32_t)w[0] | (uint32_t)w[1] << 8 | (uint32_t)w[2] << 16 | (uint32_t)w[3] << 24;
}

static double AsFloat(uint32_t bits) {
  float f;
  memcpy(&f, &bits, sizeof f);
  return f;
}

/* Where a differing word sits: in the pass output it lands in (element and word), or in the buffer. */
static void PrintFirst(const Repro* r, const Buf* b, const char* output, uint64_t offset, uint64_t elem, uint64_t at,
                       uint32_t want, uint32_t got) {
  printf("first mismatch: read-back %lu, buffer '%s' (%" PRIu64 " bytes), ", r->reads, b->label, b->bytes);
  if (strcmp(output, "-") == 0) {
    printf("an intermediate read-back (the host merges or converts it, or sizes what follows with it), word %" PRIu64, at / 4);
  } else {
    const uint64_t byte = offset + at;
    printf("pass output '%s' element %" PRIu64 " word %" PRIu64, output, byte / elem, byte % elem / 4);
  }
  printf(": expected 0x%08" PRIx32 " (%.9g) got 0x%08" PRIx32 " (%.9g)\n", want, AsFloat(want), got, AsFloat(got));
}

/* read ID BYTES FILE OUTPUT OFFSET ELEMENT_BYTES */
static void StepRead(Repro* r, char** t, int n) {
  if (n != 7) Die(kExitUsage, "sequence.txt:%d: read takes 6 fields", r->line);
  if (r->recording) Die(kExitUsage, "sequence.txt:%d: a read before the submit of recorded dispatches", r->line);
  const Buf* b = BufOf(r, t[1]);
  const uint64_t bytes = Number(r, t[2], b->bytes, "read size");
  const uint64_t offset = Number(r, t[5], (uint64_t)1 << 48, "output offset");
  const uint64_t elem = Number(r, t[6], 1 << 20, "element size");
  if (elem == 0) Die(kExitUsage, "sequence.txt:%d: element size 0", r->line);
  long got_bytes = 0;
  unsigned char* want = ReadFile(r, t[3], (long)bytes, &got_bytes);
  ++r->reads;
  unsigned long long differing = 0;
  for (uint64_t at = 0; at < bytes; at += 4) {
    const uint32_t w = WordAt(want, at, bytes), g = WordAt(b->mapped, at, bytes);
    ++r->words;
    if (w == g) continue;
    if (r->words_differing + differing == 0) PrintFirst(r, b, t[4], offset, elem, at, w, g);
    ++differing;
  }
  free(want);
  r->words_differing += differing;
  r->reads_differing += differing != 0;
}

/* ---- the sequence --------------------------------------------------------------------------------- */

static void Step(Repro* r, char** t, int n) {
  if (strcmp(t[0], "pipeline") == 0) StepPipeline(r, t, n);
  else if (strcmp(t[0], "buffer") == 0) StepBuffer(r, t, n);
  else if (strcmp(t[0], "write") == 0 || strcmp(t[0], "zero") == 0 || strcmp(t[0], "free") == 0) StepHost(r, t, n);
  else if (strcmp(t[0], "dispatch") == 0) StepDispatch(r, t, n);
  else if (strcmp(t[0], "submit") == 0 && n == 1) StepSubmit(r);
  else if (strcmp(t[0], "read") == 0) StepRead(r, t, n);
  else Die(kExitUsage, "sequence.txt:%d: unknown step '%s'", r->line, t[0]);
}

static void RunSequence(Repro* r) {
  long bytes = 0;
  r->line = 0;
  char* text = (char*)ReadFile(r, "sequence.txt", -1, &bytes);
  text = realloc(text, (size_t)bytes + 1);
  if (!text) Die(kExitVulkan, "out of host memory");
  text[bytes] = '\0';
  char* tokens[kMaxTokens];
  int header = 0;
  for (char* line = text; line && *line;) {
    char* next = strchr(line, '\n');
    if (next) *next++ = '\0';
    ++r->line;
    const int n = Tokens(line, tokens);
    if (n < 0) Die(kExitUsage, "sequence.txt:%d: more than %d fields", r->line, kMaxTokens);
    if (n > 0 && !header) {
      if (n != 2 || strcmp(tokens[0], "rayspace-repro") != 0 || strcmp(tokens[1], "1") != 0)
        Die(kExitUsage, "%s/sequence.txt: not a rayspace-repro 1 sequence", r->dir);
      header = 1;
    } else if (n > 0) {
      Step(r, tokens, n);
    }
    line = next;
  }
  if (!header) Die(kExitUsage, "%s/sequence.txt: empty", r->dir);
  StepSubmit(r);
  free(text);
}

static void Teardown(Repro* r) {
  vkDeviceWaitIdle(r->device);
  for (size_t i = 0; i < r->buf_count; ++i)
    if (r->bufs[i].live) FreeBuf(r, &r->bufs[i]);
  for (size_t i = 0; i < r->pipe_count; ++i) {
    Pipe* p = &r->pipes[i];
    if (!p->pipeline) continue;
    vkDestroyPipeline(r->device, p->pipeline, NULL);
    vkDestroyPipelineLayout(r->device, p->layout, NULL);
    vkDestroyDescriptorSetLayout(r->device, p->set_layout, NULL);
    vkDestroyShaderModule(r->device, p->module, NULL);
  }
  vkDestroyCommandPool(r->device, r->command_pool, NULL);
  vkDestroyDevice(r->device, NULL);
  if (r->messenger) {
    PFN_vkDestroyDebugUtilsMessengerEXT destroy =
        (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(r->instance, "vkDestroyDebugUtilsMessengerEXT");
    if (destroy) destroy(r->instance, r->messenger, NULL);
  }
  vkDestroyInstance(r->instance, NULL);
  free(r->bufs);
  free(r->pipes);
  free(r->pools);
}

static void ParseArgs(Repro* r, int argc, char** argv) {
  const char* env = getenv("REPRO_VALIDATE");
  r->dir = ".";
  r->device_index = -1;
  r->validate = env && *env && strcmp(env, "0") != 0;
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--validate") == 0) {
      r->validate = 1;
    } else if (strcmp(argv[i], "--device") == 0 && i + 1 < argc) {
      char* end = NULL;
      const long d = strtol(argv[++i], &end, 10);
      if (!*argv[i] || *end || d < 0 || d > 64) Die(kExitUsage, "--device '%s': expected a device index 0..64", argv[i]);
      r->device_index = (int)d;
    } else if (argv[i][0] == '-') {
      Die(kExitUsage, "unknown option '%s' (usage: repro [DIR] [--device N] [--validate])", argv[i]);
    } else {
      r->dir = argv[i];
    }
  }
}

int main(int argc, char** argv) {
  Repro r;
  memset(&r, 0, sizeof r);
  setvbuf(stdout, NULL, _IOLBF, 0);  /* each line out before a driver crash can lose it */
  ParseArgs(&r, argc, argv);
  CreateInstance(&r);
  PickDevice(&r);
  CreateDevice(&r);
  RunSequence(&r);
  Teardown(&r);
  if (r.words_differing)
    printf("mismatch: %lu of %lu read-back(s) differ, %llu of %llu words\n", r.reads_differing, r.reads, r.words_differing, r.words);
  else
    printf("equal: %lu read-back(s), %llu words\n", r.reads, r.words);
  if (g_validation_messages) {
    printf("validation: %lu message(s)\n", g_validation_messages);
    return kExitValidation;
  }
  return r.words_differing ? kExitMismatch : kExitEqual;
}
