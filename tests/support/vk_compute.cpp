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

bool Context::run(const std::vector<uint32_t>& spirv, const std::vector<std::vector<std::byte>*>& buffers,
                  const std::vector<Image>& images, const void* push, uint32_t push_size, uint32_t groups_x,
                  std::string* why) {
  Impl& v = *impl_;
  std::lock_guard<std::mutex> lock(v.mutex);
  const VkDevice dev = v.device;
  const uint32_t nb = uint32_t(buffers.size());
  std::vector<VkBuffer> bufs(nb, VK_NULL_HANDLE);
  std::vector<VkDeviceMemory> mems(nb, VK_NULL_HANDLE);
  VkShaderModule module = VK_NULL_HANDLE;
  VkDescriptorSetLayout dsl = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkCommandPool cpool = VK_NULL_HANDLE;
  const uint32_t ni = uint32_t(images.size());
  std::vector<VkImage> imgs(ni, VK_NULL_HANDLE);
  std::vector<VkImageView> views(ni, VK_NULL_HANDLE);
  std::vector<VkDeviceMemory> img_mems(ni, VK_NULL_HANDLE), staging_mems(ni, VK_NULL_HANDLE);
  std::vector<VkBuffer> staging(ni, VK_NULL_HANDLE);
  VkSampler sampler = VK_NULL_HANDLE;
  bool ok = false;
  auto fail = [&](const char* what) {
    *why = what;
    return false;
  };
  auto body = [&]() -> bool {
    for (uint32_t i = 0; i < nb; ++i)
      if (const char* e =
              host_buffer(v, std::max<size_t>(buffers[i]->size(), 16), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                          buffers[i]->data(), buffers[i]->size(), false, &bufs[i], &mems[i]))
        return fail(e);
    if (ni) {
      const VkFormatFeatureFlags need =
          VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
      if ((v.rgba32f_optimal_features & need) != need)
        return fail("device cannot linearly filter VK_FORMAT_R32G32B32A32_SFLOAT images");
      auto sci = make<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
      sci.magFilter = sci.minFilter = VK_FILTER_LINEAR;
      sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
      sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
      sci.maxLod = 0.0f;
      if (v.CreateSampler(dev, &sci, nullptr, &sampler) != VK_SUCCESS) return fail("vkCreateSampler failed");
    }
    for (uint32_t i = 0; i < ni; ++i) {
      const Image& im = images[i];
      const bool is3d = im.depth > 0;
      const uint32_t d = is3d ? im.depth : 1;
      const size_t bytes = size_t(im.width) * im.height * d * 16;
      if (!im.texels || bytes == 0) return fail("empty image");
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
      if (v.CreateImage(dev, &ici, nullptr, &imgs[i]) != VK_SUCCESS) return fail("vkCreateImage failed");
      VkMemoryRequirements req{};
      v.GetImageMemoryRequirements(dev, imgs[i], &req);
      const int type = any_memory_type(v, req.memoryTypeBits);
      if (type < 0) return fail("no memory type for the image");
      if (allocate(v, req, type, &img_mems[i]) != VK_SUCCESS) return fail("vkAllocateMemory failed (image)");
      if (v.BindImageMemory(dev, imgs[i], img_mems[i], 0) != VK_SUCCESS)
        return fail("vkBindImageMemory failed");
      auto ivci = make<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
      ivci.image = imgs[i];
      ivci.viewType = is3d ? VK_IMAGE_VIEW_TYPE_3D : VK_IMAGE_VIEW_TYPE_2D;
      ivci.format = ici.format;
      ivci.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
      if (v.CreateImageView(dev, &ivci, nullptr, &views[i]) != VK_SUCCESS)
        return fail("vkCreateImageView failed");
      if (const char* e = host_buffer(v, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, im.texels, bytes, true,
                                      &staging[i], &staging_mems[i]))
        return fail(e);
    }
    auto smci = make<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
    smci.codeSize = spirv.size() * 4;
    smci.pCode = spirv.data();
    if (v.CreateShaderModule(dev, &smci, nullptr, &module) != VK_SUCCESS)
      return fail("vkCreateShaderModule failed");
    std::vector<VkDescriptorSetLayoutBinding> binds(nb + ni);
    for (uint32_t i = 0; i < nb + ni; ++i) {
      binds[i] = {};
      binds[i].binding = i;
      binds[i].descriptorType =
          i < nb ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
      binds[i].descriptorCount = 1;
      binds[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    auto dlci = make<VkDescriptorSetLayoutCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
    dlci.bindingCount = nb + ni;
    dlci.pBindings = binds.data();
    if (v.CreateDescriptorSetLayout(dev, &dlci, nullptr, &dsl) != VK_SUCCESS)
      return fail("vkCreateDescriptorSetLayout failed");
    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size};
    auto plci = make<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
    plci.setLayoutCount = 1;
    plci.pSetLayouts = &dsl;
    plci.pushConstantRangeCount = push_size ? 1 : 0;
    plci.pPushConstantRanges = push_size ? &range : nullptr;
    if (v.CreatePipelineLayout(dev, &plci, nullptr, &layout) != VK_SUCCESS)
      return fail("vkCreatePipelineLayout failed");
    auto cpci = make<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
    cpci.stage = make<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
    cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpci.stage.module = module;
    cpci.stage.pName = "main";
    cpci.layout = layout;
    if (v.CreateComputePipelines(dev, VK_NULL_HANDLE, 1, &cpci, nullptr, &pipeline) != VK_SUCCESS)
      return fail("vkCreateComputePipelines failed");
    const VkDescriptorPoolSize ps[2] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, std::max(nb, 1u)},
                                        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, std::max(ni, 1u)}};
    auto dpci = make<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
    dpci.maxSets = 1;
    dpci.poolSizeCount = ni ? 2 : 1;
    dpci.pPoolSizes = ps;
    if (v.CreateDescriptorPool(dev, &dpci, nullptr, &pool) != VK_SUCCESS)
      return fail("vkCreateDescriptorPool failed");
    auto dsai = make<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
    dsai.descriptorPool = pool;
    dsai.descriptorSetCount = 1;
    dsai.pSetLayouts = &dsl;
    VkDescriptorSet set = VK_NULL_HANDLE;
    if (v.AllocateDescriptorSets(dev, &dsai, &set) != VK_SUCCESS)
      return fail("vkAllocateDescriptorSets failed");
    std::vector<VkDescriptorBufferInfo> infos(nb);
    std::vector<VkWriteDescriptorSet> writes(nb);
    for (uint32_t i = 0; i < nb; ++i) {
      infos[i] = {bufs[i], 0, VK_WHOLE_SIZE};
      writes[i] = make<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
      writes[i].dstSet = set;
      writes[i].dstBinding = i;
      writes[i].descriptorCount = 1;
      writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      writes[i].pBufferInfo = &infos[i];
    }
    std::vector<VkDescriptorImageInfo> img_infos(ni);
    for (uint32_t i = 0; i < ni; ++i) {
      img_infos[i] = {sampler, views[i], VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
      auto w = make<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
      w.dstSet = set;
      w.dstBinding = nb + i;
      w.descriptorCount = 1;
      w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
      w.pImageInfo = &img_infos[i];
      writes.push_back(w);
    }
    v.UpdateDescriptorSets(dev, uint32_t(writes.size()), writes.data(), 0, nullptr);
    auto cpi = make<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
    cpi.queueFamilyIndex = v.family;
    if (v.CreateCommandPool(dev, &cpi, nullptr, &cpool) != VK_SUCCESS)
      return fail("vkCreateCommandPool failed");
    auto cbai = make<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    cbai.commandPool = cpool;
    cbai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cbai.commandBufferCount = 1;
    VkCommandBuffer cb = VK_NULL_HANDLE;
    if (v.AllocateCommandBuffers(dev, &cbai, &cb) != VK_SUCCESS)
      return fail("vkAllocateCommandBuffers failed");
    auto bi = make<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    v.BeginCommandBuffer(cb, &bi);
    for (uint32_t i = 0; i < ni; ++i) {
      const Image& im = images[i];
      auto ib = make<VkImageMemoryBarrier>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER);
      ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
      ib.image = imgs[i];
      ib.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
      ib.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
      ib.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
      ib.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
      v.CmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                           nullptr, 0, nullptr, 1, &ib);
      VkBufferImageCopy region{};
      region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      region.imageExtent = {im.width, im.height, im.depth > 0 ? im.depth : 1};
      v.CmdCopyBufferToImage(cb, staging[i], imgs[i], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
      ib.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
      ib.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
      ib.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
      ib.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
      v.CmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0,
                           nullptr, 0, nullptr, 1, &ib);
    }
    v.CmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    v.CmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set, 0, nullptr);
    if (push_size) v.CmdPushConstants(cb, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size, push);
    v.CmdDispatch(cb, groups_x, 1, 1);
    auto mb = make<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    v.CmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0,
                         nullptr, 0, nullptr);
    if (v.EndCommandBuffer(cb) != VK_SUCCESS) return fail("vkEndCommandBuffer failed");
    auto si = make<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    if (v.QueueSubmit(v.queue, 1, &si, VK_NULL_HANDLE) != VK_SUCCESS) return fail("vkQueueSubmit failed");
    if (v.QueueWaitIdle(v.queue) != VK_SUCCESS) return fail("vkQueueWaitIdle failed");
    for (uint32_t i = 0; i < nb; ++i) {
      if (buffers[i]->empty()) continue;
      void* p = nullptr;
      if (v.MapMemory(dev, mems[i], 0, VK_WHOLE_SIZE, 0, &p) != VK_SUCCESS) return fail("vkMapMemory failed");
      std::memcpy(buffers[i]->data(), p, buffers[i]->size());
      v.UnmapMemory(dev, mems[i]);
    }
    return true;
  };
  ok = body();
  if (cpool) v.DestroyCommandPool(dev, cpool, nullptr);
  if (pool) v.DestroyDescriptorPool(dev, pool, nullptr);
  if (pipeline) v.DestroyPipeline(dev, pipeline, nullptr);
  if (layout) v.DestroyPipelineLayout(dev, layout, nullptr);
  if (dsl) v.DestroyDescriptorSetLayout(dev, dsl, nullptr);
  if (module) v.DestroyShaderModule(dev, module, nullptr);
  for (uint32_t i = 0; i < ni; ++i) {
    if (views[i]) v.DestroyImageView(dev, views[i], nullptr);
    if (imgs[i]) v.DestroyImage(dev, imgs[i], nullptr);
    if (img_mems[i]) v.FreeMemory(dev, img_mems[i], nullptr);
    if (staging[i]) v.DestroyBuffer(dev, staging[i], nullptr);
    if (staging_mems[i]) v.FreeMemory(dev, staging_mems[i], nullptr);
  }
  if (sampler) v.DestroySampler(dev, sampler, nullptr);
  for (uint32_t i = 0; i < nb; ++i) {
    if (bufs[i]) v.DestroyBuffer(dev, bufs[i], nullptr);
    if (mems[i]) v.FreeMemory(dev, mems[i], nullptr);
  }
  return ok;
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
