// Tiny Vulkan compute harness (see vk_compute.h). Loads libvulkan.so.1 with dlopen; no link-time dependency.
#include "vk_compute.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MSH_VK_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define MSH_VK_SANITIZED 1
#endif

#if __has_include(<vulkan/vulkan.h>) && __has_include(<dlfcn.h>)
#define MSH_VK_HAVE_HEADERS 1
#define VK_NO_PROTOTYPES
#include <dlfcn.h>
#include <vulkan/vulkan.h>
#endif

namespace msh::test::vk {

namespace fs = std::filesystem;

std::string glslang_validator() {
  if (const char* path = std::getenv("PATH")) {
    std::stringstream ss(path);
    std::string dir;
    while (std::getline(ss, dir, ':')) {
      const fs::path p = fs::path(dir) / "glslangValidator";
      if (!dir.empty() && access(p.c_str(), X_OK) == 0) return p.string();
    }
  }
  return access("/usr/bin/glslangValidator", X_OK) == 0 ? "/usr/bin/glslangValidator" : "";
}

namespace {
std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}
}  // namespace

bool compile_shader(const std::string& source, Lang lang, std::vector<uint32_t>* spirv, std::string* log,
                    const std::string& hlsl_entry) {
  const std::string tool = glslang_validator();
  if (tool.empty()) {
    *log = "glslangValidator not found (Debian package glslang-tools; scripts/install-deps.sh installs it)";
    return false;
  }
  static std::atomic<int> counter{0};
  const fs::path dir = fs::temp_directory_path() /
                       ("msh_vk_" + std::to_string(getpid()) + "_" + std::to_string(counter.fetch_add(1)));
  fs::create_directories(dir);
  const fs::path src = dir / (lang == Lang::kGlsl ? "shader.comp" : "shader.hlsl");
  const fs::path spv = dir / "shader.spv", out = dir / "log.txt";
  std::ofstream(src, std::ios::binary) << source;
  std::string cmd = "'" + tool + "' -V --target-env vulkan1.1 ";
  if (lang == Lang::kHlsl) cmd += "-D -S comp -e main --source-entrypoint '" + hlsl_entry + "' ";
  cmd += "-o '" + spv.string() + "' '" + src.string() + "' > '" + out.string() + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  *log = read_text(out);
  bool ok = rc == 0 && fs::exists(spv);
  if (ok) {
    const std::string bytes = read_text(spv);
    ok = !bytes.empty() && bytes.size() % 4 == 0;
    if (ok) {
      spirv->resize(bytes.size() / 4);
      std::memcpy(spirv->data(), bytes.data(), bytes.size());
    }
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
  return ok;
}

#ifdef MSH_VK_HAVE_HEADERS

// Function pointers, loaded at run time.
struct Context::Impl {
  void* lib = nullptr;
  PFN_vkGetInstanceProcAddr GetInstanceProcAddr = nullptr;
  PFN_vkGetDeviceProcAddr GetDeviceProcAddr = nullptr;
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice phys = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t family = 0;
  VkPhysicalDeviceMemoryProperties mem{};
  VkFormatFeatureFlags rgba32f_optimal_features = 0;
  std::mutex mutex;

#define MSH_VK_DEVICE_FNS(X)                                                                                \
  X(GetDeviceQueue)                                                                                         \
  X(CreateBuffer)                                                                                           \
  X(DestroyBuffer)                                                                                          \
  X(GetBufferMemoryRequirements) X(AllocateMemory) X(FreeMemory) X(BindBufferMemory) X(MapMemory)           \
      X(UnmapMemory) X(CreateShaderModule) X(DestroyShaderModule) X(CreateDescriptorSetLayout)              \
          X(DestroyDescriptorSetLayout) X(CreatePipelineLayout) X(DestroyPipelineLayout)                    \
              X(CreateComputePipelines) X(DestroyPipeline) X(CreateDescriptorPool) X(DestroyDescriptorPool) \
                  X(AllocateDescriptorSets) X(UpdateDescriptorSets) X(CreateCommandPool)                    \
                      X(DestroyCommandPool) X(AllocateCommandBuffers) X(BeginCommandBuffer)                 \
                          X(EndCommandBuffer) X(CmdBindPipeline) X(CmdBindDescriptorSets)                   \
                              X(CmdPushConstants) X(CmdDispatch) X(CmdPipelineBarrier) X(QueueSubmit)       \
                                  X(QueueWaitIdle) X(DestroyDevice) MSH_VK_IMAGE_FNS(X)
// Added for sampled-image tests (run() with images).
#define MSH_VK_IMAGE_FNS(X)                                                                                \
  X(CreateImage)                                                                                           \
  X(DestroyImage)                                                                                          \
  X(GetImageMemoryRequirements) X(BindImageMemory) X(CreateImageView) X(DestroyImageView) X(CreateSampler) \
      X(DestroySampler) X(CmdCopyBufferToImage)
#define MSH_VK_DECLARE(name) PFN_vk##name name = nullptr;
  MSH_VK_DEVICE_FNS(MSH_VK_DECLARE)
#undef MSH_VK_DECLARE
};

namespace {

// A zero-initialized Vulkan struct with its sType set.
template <class T>
T make(VkStructureType type) {
  T t{};
  t.sType = type;
  return t;
}

[[maybe_unused]] bool init(Context::Impl& v, std::string* name, std::string* why) {
  v.lib = dlopen("libvulkan.so.1", RTLD_NOW | RTLD_LOCAL);
  if (!v.lib) return *why = "libvulkan.so.1 not found (Debian package libvulkan1)", false;
  v.GetInstanceProcAddr = reinterpret_cast<PFN_vkGetInstanceProcAddr>(dlsym(v.lib, "vkGetInstanceProcAddr"));
  if (!v.GetInstanceProcAddr) return *why = "vkGetInstanceProcAddr missing", false;
  auto CreateInstance =
      reinterpret_cast<PFN_vkCreateInstance>(v.GetInstanceProcAddr(VK_NULL_HANDLE, "vkCreateInstance"));
  auto app = make<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = "microshadow-tests";
  app.apiVersion = VK_API_VERSION_1_1;
  auto ici = make<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  ici.pApplicationInfo = &app;
  if (!CreateInstance || CreateInstance(&ici, nullptr, &v.instance) != VK_SUCCESS)
    return *why = "vkCreateInstance failed (no Vulkan driver? Debian package mesa-vulkan-drivers)", false;
#define MSH_VK_INSTANCE_FN(name) \
  auto name = reinterpret_cast<PFN_vk##name>(v.GetInstanceProcAddr(v.instance, "vk" #name));
  MSH_VK_INSTANCE_FN(EnumeratePhysicalDevices)
  MSH_VK_INSTANCE_FN(GetPhysicalDeviceProperties)
  MSH_VK_INSTANCE_FN(GetPhysicalDeviceQueueFamilyProperties)
  MSH_VK_INSTANCE_FN(GetPhysicalDeviceMemoryProperties)
  MSH_VK_INSTANCE_FN(CreateDevice)
  MSH_VK_INSTANCE_FN(GetPhysicalDeviceFormatProperties)
#undef MSH_VK_INSTANCE_FN
  v.GetDeviceProcAddr =
      reinterpret_cast<PFN_vkGetDeviceProcAddr>(v.GetInstanceProcAddr(v.instance, "vkGetDeviceProcAddr"));
  if (!EnumeratePhysicalDevices || !GetPhysicalDeviceProperties || !GetPhysicalDeviceQueueFamilyProperties ||
      !GetPhysicalDeviceMemoryProperties || !CreateDevice || !v.GetDeviceProcAddr)
    return *why = "Vulkan instance functions missing", false;
  uint32_t n = 0;
  EnumeratePhysicalDevices(v.instance, &n, nullptr);
  std::vector<VkPhysicalDevice> devs(n);
  if (n) EnumeratePhysicalDevices(v.instance, &n, devs.data());
  for (VkPhysicalDevice d : devs) {
    uint32_t nf = 0;
    GetPhysicalDeviceQueueFamilyProperties(d, &nf, nullptr);
    std::vector<VkQueueFamilyProperties> fams(nf);
    GetPhysicalDeviceQueueFamilyProperties(d, &nf, fams.data());
    for (uint32_t f = 0; f < nf; ++f)
      if (fams[f].queueFlags & VK_QUEUE_COMPUTE_BIT) {
        v.phys = d, v.family = f;
        break;
      }
    if (v.phys) break;
  }
  if (!v.phys) return *why = "no Vulkan device with a compute queue", false;
  VkPhysicalDeviceProperties props{};
  GetPhysicalDeviceProperties(v.phys, &props);
  *name = props.deviceName;
  GetPhysicalDeviceMemoryProperties(v.phys, &v.mem);
  if (GetPhysicalDeviceFormatProperties) {
    VkFormatProperties fp{};
    GetPhysicalDeviceFormatProperties(v.phys, VK_FORMAT_R32G32B32A32_SFLOAT, &fp);
    v.rgba32f_optimal_features = fp.optimalTilingFeatures;
  }
  const float prio = 1.0f;
  auto qci = make<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  qci.queueFamilyIndex = v.family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &prio;
  auto dci = make<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  if (CreateDevice(v.phys, &dci, nullptr, &v.device) != VK_SUCCESS)
    return *why = "vkCreateDevice failed", false;
#define MSH_VK_LOAD(name)                                                             \
  v.name = reinterpret_cast<PFN_vk##name>(v.GetDeviceProcAddr(v.device, "vk" #name)); \
  if (!v.name) return *why = "Vulkan device function vk" #name " missing", false;
  MSH_VK_DEVICE_FNS(MSH_VK_LOAD)
#undef MSH_VK_LOAD
  v.GetDeviceQueue(v.device, v.family, 0, &v.queue);
  return true;
}

int host_memory_type(const Context::Impl& v, uint32_t bits) {
  const VkMemoryPropertyFlags want =
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  for (uint32_t i = 0; i < v.mem.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (v.mem.memoryTypes[i].propertyFlags & want) == want) return int(i);
  return -1;
}

int any_memory_type(const Context::Impl& v, uint32_t bits) {
  for (uint32_t i = 0; i < v.mem.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (v.mem.memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT))
      return int(i);
  for (uint32_t i = 0; i < v.mem.memoryTypeCount; ++i)
    if (bits & (1u << i)) return int(i);
  return -1;
}

// req.size bytes of memory of `type`.
VkResult allocate(const Context::Impl& v, const VkMemoryRequirements& req, int type, VkDeviceMemory* mem) {
  auto mai = make<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = uint32_t(type);
  return v.AllocateMemory(v.device, &mai, nullptr, mem);
}

// A buffer of `size` bytes for `usage` in host-visible coherent memory, holding the n bytes at `data` and
// zeros after them: nullptr, or what failed (the staging buffers of images say so in their messages).
const char* host_buffer(const Context::Impl& v, VkDeviceSize size, VkBufferUsageFlags usage, const void* data,
                        size_t n, bool staging, VkBuffer* buf, VkDeviceMemory* mem) {
  auto bci = make<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  bci.size = size;
  bci.usage = usage;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  if (v.CreateBuffer(v.device, &bci, nullptr, buf) != VK_SUCCESS)
    return staging ? "vkCreateBuffer failed (staging)" : "vkCreateBuffer failed";
  VkMemoryRequirements req{};
  v.GetBufferMemoryRequirements(v.device, *buf, &req);
  const int type = host_memory_type(v, req.memoryTypeBits);
  if (type < 0) return "no host-visible coherent memory type";
  if (allocate(v, req, type, mem) != VK_SUCCESS)
    return staging ? "vkAllocateMemory failed (staging)" : "vkAllocateMemory failed";
  if (v.BindBufferMemory(v.device, *buf, *mem, 0) != VK_SUCCESS)
    return staging ? "vkBindBufferMemory failed (staging)" : "vkBindBufferMemory failed";
  void* p = nullptr;
  if (v.MapMemory(v.device, *mem, 0, VK_WHOLE_SIZE, 0, &p) != VK_SUCCESS) return "vkMapMemory failed";
  std::memset(p, 0, size);
  if (n) std::memcpy(p, data, n);
  v.UnmapMemory(v.device, *mem);
  return nullptr;
}

}  // namespace

Context* Context::get(std::string* why) {
  static std::once_flag once;
  static Context* ctx = nullptr;
  static std::string reason;
  std::call_once(once, [] {
#ifdef MSH_VK_SANITIZED
    reason = "Vulkan run skipped in sanitizer builds (the driver's JIT and allocations are not instrumented)";
#else
    auto* c = new Context;
    c->impl_ = new Impl;
    if (init(*c->impl_, &c->device_name_, &reason)) ctx = c;  // kept for the process lifetime
#endif
  });
  if (!ctx) {
    if (why) *why = reason;
    // A missing device must not pass silently: the run part of every shader test would be skipped and the
    // suite would look green. Skipping is allowed only when asked for (or in sanitizer builds, which never
    // run the driver).
#ifndef MSH_VK_SANITIZED
    if (!no_vulkan_allowed())
      ADD_FAILURE() << "no Vulkan compute device (" << reason
                    << "); set MSH_ALLOW_NO_VULKAN=1 to allow skipping the Vulkan runs";
#endif
  }
  return ctx;
}

bool no_vulkan_allowed() {
  const char* e = std::getenv("MSH_ALLOW_NO_VULKAN");
  return e != nullptr && std::strcmp(e, "1") == 0;
}

bool Context::run(const std::vector<uint32_t>& spirv, const std::vector<std::vector<std::byte>*>& buffers,
                  const void* push, uint32_t push_size, uint32_t groups_x, std::string* why) {
  return run(spirv, buffers, {}, push, push_size, groups_x, why);
}

namespace {

// The objects of one dispatch. Each step creates some and returns nullptr or what failed; the destructor
// destroys whatever exists, dependants first, so a run that fails at any step leaves nothing behind.
class Dispatch {
 public:
  using Buffers = std::vector<std::vector<std::byte>*>;
  using Images = std::vector<Context::Image>;

  Dispatch(const Context::Impl& v, const Buffers& buffers, const Images& images)
      : v_(v),
        dev_(v.device),
        buffers_(buffers),
        images_(images),
        storage_(buffers.size()),
        sampled_(images.size()) {}
  Dispatch(const Dispatch&) = delete;
  Dispatch& operator=(const Dispatch&) = delete;
  ~Dispatch();

  const char* upload();
  const char* pipeline(const std::vector<uint32_t>& spirv, uint32_t push_size);
  const char* descriptors();
  const char* submit(const void* push, uint32_t push_size, uint32_t groups_x);
  const char* download();

 private:
  struct HostBuffer {
    VkBuffer buffer{};
    VkDeviceMemory memory{};
  };
  // A sampled image in device memory, filled from a host staging buffer.
  struct Sampled {
    VkImage image{};
    VkDeviceMemory memory{};
    VkImageView view{};
    HostBuffer staging;
  };

  const char* upload_image(const Context::Image& im, Sampled& s);
  void record_image_copies(VkCommandBuffer cb);
  uint32_t nb() const { return uint32_t(storage_.size()); }
  uint32_t ni() const { return uint32_t(sampled_.size()); }

  const Context::Impl& v_;
  const VkDevice dev_;
  const Buffers& buffers_;
  const Images& images_;
  std::vector<HostBuffer> storage_;
  std::vector<Sampled> sampled_;
  VkSampler sampler_{};
  VkShaderModule module_{};
  VkDescriptorSetLayout set_layout_{};
  VkPipelineLayout pipeline_layout_{};
  VkPipeline pipeline_{};
  VkDescriptorPool pool_{};
  VkDescriptorSet set_{};  // freed with its pool
  VkCommandPool command_pool_{};
};

Dispatch::~Dispatch() {
  if (command_pool_) v_.DestroyCommandPool(dev_, command_pool_, nullptr);
  if (pool_) v_.DestroyDescriptorPool(dev_, pool_, nullptr);
  if (pipeline_) v_.DestroyPipeline(dev_, pipeline_, nullptr);
  if (pipeline_layout_) v_.DestroyPipelineLayout(dev_, pipeline_layout_, nullptr);
  if (set_layout_) v_.DestroyDescriptorSetLayout(dev_, set_layout_, nullptr);
  if (module_) v_.DestroyShaderModule(dev_, module_, nullptr);
  auto free_buffer = [&](const HostBuffer& b) {
    if (b.buffer) v_.DestroyBuffer(dev_, b.buffer, nullptr);
    if (b.memory) v_.FreeMemory(dev_, b.memory, nullptr);
  };
  for (const Sampled& s : sampled_) {
    if (s.view) v_.DestroyImageView(dev_, s.view, nullptr);
    if (s.image) v_.DestroyImage(dev_, s.image, nullptr);
    if (s.memory) v_.FreeMemory(dev_, s.memory, nullptr);
    free_buffer(s.staging);
  }
  if (sampler_) v_.DestroySampler(dev_, sampler_, nullptr);
  for (const HostBuffer& b : storage_) free_buffer(b);
}

// The storage buffers (at least 16 bytes: a zero-size buffer is invalid), then the sampler and the images.
const char* Dispatch::upload() {
  for (uint32_t i = 0; i < nb(); ++i)
    if (const char* e = host_buffer(v_, std::max<size_t>(buffers_[i]->size(), 16),
                                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, buffers_[i]->data(),
                                    buffers_[i]->size(), false, &storage_[i].buffer, &storage_[i].memory))
      return e;
  if (ni() == 0) return nullptr;
  const VkFormatFeatureFlags need =
      VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
  if ((v_.rgba32f_optimal_features & need) != need)
    return "device cannot linearly filter VK_FORMAT_R32G32B32A32_SFLOAT images";
  auto sci = make<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
  sci.magFilter = sci.minFilter = VK_FILTER_LINEAR;
  sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  sci.maxLod = 0.0f;
  if (v_.CreateSampler(dev_, &sci, nullptr, &sampler_) != VK_SUCCESS) return "vkCreateSampler failed";
  for (uint32_t i = 0; i < ni(); ++i)
    if (const char* e = upload_image(images_[i], sampled_[i])) return e;
  return nullptr;
}

const char* Dispatch::upload_image(const Context::Image& im, Sampled& s) {
  const bool is3d = im.depth > 0;
  const uint32_t d = is3d ? im.depth : 1;
  const size_t bytes = size_t(im.width) * im.height * d * 16;
  if (!im.texels || bytes == 0) return "empty image";
  auto ici = make<VkImageCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO);
  ici.imageType = is3d ? VK_IMAGE_TYPE_3D : VK_IMAGE_TYPE_2D;
  ici.format = VK_FORMAT_R32G32B32A32_SFLOAT;
  ici.extent = {im.width, im.height, d};
  ici.mipLevels = 1;
  ici.arrayLayers = 1;
  ici.samples = VK_SAMPLE_COUNT_1_BIT;
  ici.tiling = VK_IMAGE_TILING_OPTIMAL;
  ici.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  ici.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ici.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  if (v_.CreateImage(dev_, &ici, nullptr, &s.image) != VK_SUCCESS) return "vkCreateImage failed";
  VkMemoryRequirements req{};
  v_.GetImageMemoryRequirements(dev_, s.image, &req);
  const int type = any_memory_type(v_, req.memoryTypeBits);
  if (type < 0) return "no memory type for the image";
  if (allocate(v_, req, type, &s.memory) != VK_SUCCESS) return "vkAllocateMemory failed (image)";
  if (v_.BindImageMemory(dev_, s.image, s.memory, 0) != VK_SUCCESS) return "vkBindImageMemory failed";
  auto ivci = make<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
  ivci.image = s.image;
  ivci.viewType = is3d ? VK_IMAGE_VIEW_TYPE_3D : VK_IMAGE_VIEW_TYPE_2D;
  ivci.format = ici.format;
  ivci.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  if (v_.CreateImageView(dev_, &ivci, nullptr, &s.view) != VK_SUCCESS) return "vkCreateImageView failed";
  return host_buffer(v_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, im.texels, bytes, true, &s.staging.buffer,
                     &s.staging.memory);
}

// Shader module, set layout (storage buffers, then combined image samplers), pipeline layout and pipeline.
const char* Dispatch::pipeline(const std::vector<uint32_t>& spirv, uint32_t push_size) {
  auto smci = make<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
  smci.codeSize = spirv.size() * 4;
  smci.pCode = spirv.data();
  if (v_.CreateShaderModule(dev_, &smci, nullptr, &module_) != VK_SUCCESS)
    return "vkCreateShaderModule failed";
  std::vector<VkDescriptorSetLayoutBinding> binds(nb() + ni());
  for (uint32_t i = 0; i < nb() + ni(); ++i) {
    binds[i] = {};
    binds[i].binding = i;
    binds[i].descriptorType =
        i < nb() ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    binds[i].descriptorCount = 1;
    binds[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  auto dlci = make<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
  dlci.bindingCount = nb() + ni();
  dlci.pBindings = binds.data();
  if (v_.CreateDescriptorSetLayout(dev_, &dlci, nullptr, &set_layout_) != VK_SUCCESS)
    return "vkCreateDescriptorSetLayout failed";
  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size};
  auto plci = make<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  plci.setLayoutCount = 1;
  plci.pSetLayouts = &set_layout_;
  plci.pushConstantRangeCount = push_size ? 1 : 0;
  plci.pPushConstantRanges = push_size ? &range : nullptr;
  if (v_.CreatePipelineLayout(dev_, &plci, nullptr, &pipeline_layout_) != VK_SUCCESS)
    return "vkCreatePipelineLayout failed";
  auto cpci = make<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
  cpci.stage = make<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
  cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  cpci.stage.module = module_;
  cpci.stage.pName = "main";
  cpci.layout = pipeline_layout_;
  if (v_.CreateComputePipelines(dev_, VK_NULL_HANDLE, 1, &cpci, nullptr, &pipeline_) != VK_SUCCESS)
    return "vkCreateComputePipelines failed";
  return nullptr;
}

// One descriptor set: the storage buffers at bindings 0 .. nb-1, the images at nb .. nb+ni-1.
const char* Dispatch::descriptors() {
  const VkDescriptorPoolSize ps[2] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, std::max(nb(), 1u)},
                                      {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, std::max(ni(), 1u)}};
  auto dpci = make<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  dpci.maxSets = 1;
  dpci.poolSizeCount = ni() ? 2 : 1;
  dpci.pPoolSizes = ps;
  if (v_.CreateDescriptorPool(dev_, &dpci, nullptr, &pool_) != VK_SUCCESS)
    return "vkCreateDescriptorPool failed";
  auto dsai = make<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  dsai.descriptorPool = pool_;
  dsai.descriptorSetCount = 1;
  dsai.pSetLayouts = &set_layout_;
  if (v_.AllocateDescriptorSets(dev_, &dsai, &set_) != VK_SUCCESS) return "vkAllocateDescriptorSets failed";
  std::vector<VkDescriptorBufferInfo> infos(nb());
  std::vector<VkDescriptorImageInfo> img_infos(ni());
  std::vector<VkWriteDescriptorSet> writes(nb() + ni());
  for (uint32_t i = 0; i < nb() + ni(); ++i) {
    VkWriteDescriptorSet& w = writes[i] = make<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    w.dstSet = set_;
    w.dstBinding = i;
    w.descriptorCount = 1;
    if (i < nb()) {
      infos[i] = {storage_[i].buffer, 0, VK_WHOLE_SIZE};
      w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      w.pBufferInfo = &infos[i];
    } else {
      img_infos[i - nb()] = {sampler_, sampled_[i - nb()].view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
      w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
      w.pImageInfo = &img_infos[i - nb()];
    }
  }
  v_.UpdateDescriptorSets(dev_, uint32_t(writes.size()), writes.data(), 0, nullptr);
  return nullptr;
}

// Staging buffer → image, each image moved to the layout the shader reads.
void Dispatch::record_image_copies(VkCommandBuffer cb) {
  for (uint32_t i = 0; i < ni(); ++i) {
    const Context::Image& im = images_[i];
    auto ib = make<VkImageMemoryBarrier>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER);
    ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    ib.image = sampled_[i].image;
    ib.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    ib.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    ib.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    ib.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    v_.CmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                          nullptr, 0, nullptr, 1, &ib);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {im.width, im.height, im.depth > 0 ? im.depth : 1};
    v_.CmdCopyBufferToImage(cb, sampled_[i].staging.buffer, sampled_[i].image,
                            VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    ib.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    ib.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    ib.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    ib.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
    v_.CmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0,
                          nullptr, 0, nullptr, 1, &ib);
  }
}

// One command buffer: the image uploads, the dispatch, a barrier that makes its writes visible to the host;
// submitted and waited for.
const char* Dispatch::submit(const void* push, uint32_t push_size, uint32_t groups_x) {
  auto cpi = make<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  cpi.queueFamilyIndex = v_.family;
  if (v_.CreateCommandPool(dev_, &cpi, nullptr, &command_pool_) != VK_SUCCESS)
    return "vkCreateCommandPool failed";
  auto cbai = make<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  cbai.commandPool = command_pool_;
  cbai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cbai.commandBufferCount = 1;
  VkCommandBuffer cb = VK_NULL_HANDLE;  // freed with its pool
  if (v_.AllocateCommandBuffers(dev_, &cbai, &cb) != VK_SUCCESS) return "vkAllocateCommandBuffers failed";
  auto bi = make<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  v_.BeginCommandBuffer(cb, &bi);
  record_image_copies(cb);
  v_.CmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  v_.CmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout_, 0, 1, &set_, 0, nullptr);
  if (push_size) v_.CmdPushConstants(cb, pipeline_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size, push);
  v_.CmdDispatch(cb, groups_x, 1, 1);
  auto mb = make<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  v_.CmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0,
                        nullptr, 0, nullptr);
  if (v_.EndCommandBuffer(cb) != VK_SUCCESS) return "vkEndCommandBuffer failed";
  auto si = make<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cb;
  if (v_.QueueSubmit(v_.queue, 1, &si, VK_NULL_HANDLE) != VK_SUCCESS) return "vkQueueSubmit failed";
  if (v_.QueueWaitIdle(v_.queue) != VK_SUCCESS) return "vkQueueWaitIdle failed";
  return nullptr;
}

// Every storage buffer back into the caller's bytes.
const char* Dispatch::download() {
  for (uint32_t i = 0; i < nb(); ++i) {
    if (buffers_[i]->empty()) continue;
    void* p = nullptr;
    if (v_.MapMemory(dev_, storage_[i].memory, 0, VK_WHOLE_SIZE, 0, &p) != VK_SUCCESS)
      return "vkMapMemory failed";
    std::memcpy(buffers_[i]->data(), p, buffers_[i]->size());
    v_.UnmapMemory(dev_, storage_[i].memory);
  }
  return nullptr;
}

}  // namespace

bool Context::run(const std::vector<uint32_t>& spirv, const std::vector<std::vector<std::byte>*>& buffers,
                  const std::vector<Image>& images, const void* push, uint32_t push_size, uint32_t groups_x,
                  std::string* why) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  Dispatch d(*impl_, buffers, images);
  const char* e = d.upload();
  if (!e) e = d.pipeline(spirv, push_size);
  if (!e) e = d.descriptors();
  if (!e) e = d.submit(push, push_size, groups_x);
  if (!e) e = d.download();
  if (e) *why = e;
  return e == nullptr;
}

#else  // no Vulkan headers at build time

struct Context::Impl {};
Context* Context::get(std::string* why) {
  if (why) *why = "built without Vulkan headers (Debian package libvulkan-dev)";
  return nullptr;
}
bool Context::run(const std::vector<uint32_t>&, const std::vector<std::vector<std::byte>*>&, const void*,
                  uint32_t, uint32_t, std::string* why) {
  *why = "built without Vulkan headers";
  return false;
}
bool Context::run(const std::vector<uint32_t>&, const std::vector<std::vector<std::byte>*>&,
                  const std::vector<Image>&, const void*, uint32_t, uint32_t, std::string* why) {
  *why = "built without Vulkan headers";
  return false;
}

#endif

}  // namespace msh::test::vk
