// Executes the generated shader includes: gtbake_tables.glsl and gtbake_tables.hlsl are compiled to
// SPIR-V with glslangValidator and run as Vulkan compute shaders on Mesa's CPU device (lavapipe),
// evaluating the 3D and 4D lookups, the cone model, multi-bounce and the closed-form S3 at 4,096
// random points; the results are compared with the C++ lookup code the header ships
// (runtime/gtso_runtime.h) on the same texels. Tables: the export test fixture, exported by
// this test into a temporary directory; textures uploaded as BC4_UNORM (when the device samples 3D
// BC4) and R16_UNORM.
//
// Tolerances (per point, float32 on both sides):
// - lookups: |shader - C++| <= D (3 * 2^-9 + 1e-3) + 2e-6 (+ 1/255 for BC4), D = max - min of the
//   8 texels of the trilinear footprint (the worse of the two fetches in 4D). The device filters
//   with 8 bits of sub-texel precision (VkPhysicalDeviceLimits::subTexelPrecisionBits, checked),
//   so each of the three weights may be off by 2^-9, moving the result by up to 2^-9 D each; the
//   1e-3 D covers the texture coordinate (the shader's log-form asinh and the device's acos/atan
//   against libm). lavapipe decodes and filters BC4 in 8 bits: + 2/255.
// - closed-form S3: the function's change under the device's float errors of its intermediate
//   values (closedFormTolerance).
// - cone model: the device's sin/cos/acos are far less exact than libm (Vulkan only requires
//   2^-11 absolute for sin/cos), so the tolerance is the model's sensitivity to errors of 2^-11
//   in each angle and each acos argument (coneTolerance), plus 1e-4. Multi-bounce: 1e-5.
#include <gtest/gtest.h>
#include <unistd.h>
#include <vulkan/vulkan.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "common/atomic_file.h"
#include "encode/encode_command.h"
#include "export/export_command.h"
#include "export_fixture.h"
#include "runtime/gtso_runtime.h"

namespace {

namespace fs = std::filesystem;
constexpr int kPoints = 4096;
constexpr int kLocalSize = 64;
// Per unit of texel range in the footprint: three 8-bit filter weights off by 2^-9 each, plus the
// texture coordinate's transcendental error (see the file comment).
constexpr float kFilterTolerance = 3.0f / 512.0f + 1e-3f;
// lavapipe decodes BC4 blocks to UNORM8 and returns the filtered value as UNORM8 (every BC4
// result is a multiple of 1/255; a texel centre reads 191/255 where the D3D float decode gives
// 0.7507): up to 1/255 from the decode and 1/255 from the output.
constexpr float kBc4DecodeTolerance = 2.0f / 255.0f;

#define VK_CHECK(call)                                                                      \
  do {                                                                                      \
    const VkResult r_ = (call);                                                             \
    if (r_ != VK_SUCCESS) throw std::runtime_error(#call " failed: " + std::to_string(r_)); \
  } while (0)

struct Input {
  float A, cosBeta, rp, cosThetaO;
};

// ---- the exported fixture ----
struct Exported {
  fs::path dir;
  std::string glsl, hlsl;
  std::vector<std::uint8_t> bc4[2], r16[2];  // payloads of gtso3d / gtso4d
  float coeffs[6] = {};
  float u = 0.0f;
  float closedForm[gtbake::kGtsoS3ClosedFormCoeffs] = {};  // gtso.json closed_form (fixture)
};

std::vector<std::uint8_t> ddsPayload(const fs::path& path) {
  const std::string bytes = gtbake::readFile(path);
  constexpr std::size_t kHeader = 4 + 124 + 20;  // magic, DDS_HEADER, DDS_HEADER_DXT10
  return std::vector<std::uint8_t>(bytes.begin() + kHeader, bytes.end());
}

Exported exportFixture() {
  Exported e;
  e.dir = fs::temp_directory_path() / ("gtbake_shader_test_" + std::to_string(::getpid()));
  fs::remove_all(e.dir);
  gtbake::test::writeFixture(e.dir);
  gtbake::EncodeOptions c;
  c.gtso = e.dir / "gtso";
  c.out = e.dir / "out";
  c.progress = false;
  c.force_layout_3d = gtbake::test::kFixtureLayout3D;  // permuted volumes (export_fixture.h)
  c.force_layout_4d = gtbake::test::kFixtureLayout4D;
  c.layout_lobes = 16;
  gtbake::runEncode(c);
  gtbake::ExportOptions o;
  o.fit = e.dir / "fit.json";
  o.gtso = e.dir / "gtso";
  o.out = e.dir / "out";
  gtbake::runExport(o);
  e.glsl = gtbake::readFile(e.dir / "out" / "gtbake_tables.glsl");
  e.hlsl = gtbake::readFile(e.dir / "out" / "gtbake_tables.hlsl");
  const char* base[2] = {"gtso3d", "gtso4d"};
  for (int t = 0; t < 2; ++t) {
    e.bc4[t] = ddsPayload(e.dir / "out" / (std::string(base[t]) + ".dds"));
    e.r16[t] = ddsPayload(e.dir / "out" / (std::string(base[t]) + "_r16.dds"));
  }
  for (int i = 0; i < 6; ++i) e.coeffs[i] = static_cast<float>(gtbake::test::kFixtureCoeffs[i]);
  e.u = static_cast<float>(gtbake::test::kFixtureU);
  static_assert(std::size(gtbake::test::kFixtureS3ClosedForm) == gtbake::kGtsoS3ClosedFormCoeffs);
  for (int i = 0; i < gtbake::kGtsoS3ClosedFormCoeffs; ++i) {
    e.closedForm[i] = static_cast<float>(gtbake::test::kFixtureS3ClosedForm[i]);
  }
  return e;
}

// ---- shader sources and SPIR-V ----
const char* kGlslMain = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Inputs { vec4 inputs[]; };
layout(std430, binding = 1) writeonly buffer Outputs { vec4 outputs[]; };
layout(binding = 2) uniform sampler3D table3D;
layout(binding = 3) uniform sampler3D table4D;
void main() {
  uint i = gl_GlobalInvocationID.x;
  vec4 p = inputs[i];
  outputs[2 * i] = vec4(gtso3DSample(table3D, p.x, p.y, p.z),
                        gtso4DSample(table4D, p.x, p.y, p.z, p.w), gtsoConeModel(p.x, p.y, p.z),
                        multiBounce(p.x, p.w));
  outputs[2 * i + 1] = vec4(gtsoS3ClosedForm(p.x, p.y, p.z), 0.0, 0.0, 0.0);
}
)";

const char* kHlslMain = R"(
[[vk::binding(0)]] StructuredBuffer<float4> inputs;
[[vk::binding(1)]] RWStructuredBuffer<float4> outputs;
[[vk::binding(2)]] Texture3D<float> table3D;
[[vk::binding(3)]] Texture3D<float> table4D;
[[vk::binding(4)]] SamplerState linearClamp;
[numthreads(64, 1, 1)] void main(uint3 id : SV_DispatchThreadID) {
  float4 p = inputs[id.x];
  outputs[2 * id.x] = float4(gtso3DSample(table3D, linearClamp, p.x, p.y, p.z),
                             gtso4DSample(table4D, linearClamp, p.x, p.y, p.z, p.w),
                             gtsoConeModel(p.x, p.y, p.z), multiBounce(p.x, p.w));
  outputs[2 * id.x + 1] = float4(gtsoS3ClosedForm(p.x, p.y, p.z), 0.0, 0.0, 0.0);
}
)";

std::vector<std::uint32_t> compile(const fs::path& dir, const std::string& source, bool hlsl) {
  const fs::path src = dir / (hlsl ? "main.hlsl" : "main.comp");
  const fs::path spv = dir / (hlsl ? "hlsl.spv" : "glsl.spv");
  std::ofstream(src) << source;
  const std::string cmd = std::string(GTBAKE_GLSLANG) + " -V " +
                          (hlsl ? "-D -e main -S comp " : "-S comp ") + src.string() + " -o " +
                          spv.string() + " > " + (dir / "glslang.log").string() + " 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    throw std::runtime_error("glslangValidator failed:\n" + gtbake::readFile(dir / "glslang.log"));
  }
  const std::string bytes = gtbake::readFile(spv);
  std::vector<std::uint32_t> words(bytes.size() / 4);
  std::memcpy(words.data(), bytes.data(), words.size() * 4);
  return words;
}

// ---- a minimal Vulkan compute harness ----
class Vulkan {
 public:
  Vulkan() {
    VkApplicationInfo app{};
    app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo ici{};
    ici.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
    ici.pApplicationInfo = &app;
    VK_CHECK(vkCreateInstance(&ici, nullptr, &instance_));
    std::uint32_t n = 0;
    VK_CHECK(vkEnumeratePhysicalDevices(instance_, &n, nullptr));
    std::vector<VkPhysicalDevice> devices(n);
    VK_CHECK(vkEnumeratePhysicalDevices(instance_, &n, devices.data()));
    for (VkPhysicalDevice d : devices) {
      VkPhysicalDeviceProperties p;
      vkGetPhysicalDeviceProperties(d, &p);
      if (p.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) {
        physical_ = d;
        deviceName = p.deviceName;
        subTexelBits = p.limits.subTexelPrecisionBits;
      }
    }
    if (physical_ == VK_NULL_HANDLE) {
      throw std::runtime_error("no CPU Vulkan device (install mesa-vulkan-drivers: lavapipe)");
    }
    std::uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &qn, nullptr);
    std::vector<VkQueueFamilyProperties> qf(qn);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &qn, qf.data());
    for (std::uint32_t i = 0; i < qn; ++i)
      if (qf[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
        family_ = i;
        break;
      }
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{};
    qci.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
    qci.queueFamilyIndex = family_;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    VkPhysicalDeviceFeatures features{};
    VkPhysicalDeviceFeatures supported;
    vkGetPhysicalDeviceFeatures(physical_, &supported);
    features.textureCompressionBC = supported.textureCompressionBC;
    VkDeviceCreateInfo dci{};
    dci.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.pEnabledFeatures = &features;
    VK_CHECK(vkCreateDevice(physical_, &dci, nullptr, &device_));
    vkGetDeviceQueue(device_, family_, 0, &queue_);
    VkCommandPoolCreateInfo pci{};
    pci.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    pci.queueFamilyIndex = family_;
    VK_CHECK(vkCreateCommandPool(device_, &pci, nullptr, &pool_));
    VkSamplerCreateInfo sci{};
    sci.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO;
    sci.magFilter = sci.minFilter = VK_FILTER_LINEAR;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    sci.maxLod = 0.0f;
    VK_CHECK(vkCreateSampler(device_, &sci, nullptr, &sampler_));
  }
  ~Vulkan() {
    for (auto& i : images_) {
      vkDestroyImageView(device_, i.view, nullptr);
      vkDestroyImage(device_, i.image, nullptr);
      vkFreeMemory(device_, i.memory, nullptr);
    }
    for (auto& b : buffers_) {
      vkDestroyBuffer(device_, b.buffer, nullptr);
      vkFreeMemory(device_, b.memory, nullptr);
    }
    vkDestroySampler(device_, sampler_, nullptr);
    vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
    vkDestroyInstance(instance_, nullptr);
  }

  bool samples3D(VkFormat format) const {
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(physical_, format, &fp);
    if (!(fp.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT))
      return false;
    VkImageFormatProperties ip;
    return vkGetPhysicalDeviceImageFormatProperties(
               physical_, format, VK_IMAGE_TYPE_3D, VK_IMAGE_TILING_OPTIMAL,
               VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, 0, &ip) == VK_SUCCESS;
  }

  // A host-visible buffer with `bytes` of data (or zeros); returns its index.
  int buffer(std::size_t bytes, const void* data, VkBufferUsageFlags usage) {
    Buffer b;
    VkBufferCreateInfo bci{};
    bci.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    bci.size = bytes;
    bci.usage = usage;
    VK_CHECK(vkCreateBuffer(device_, &bci, nullptr, &b.buffer));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device_, b.buffer, &req);
    b.memory =
        allocate(req, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    VK_CHECK(vkBindBufferMemory(device_, b.buffer, b.memory, 0));
    b.size = bytes;
    void* p = nullptr;
    VK_CHECK(vkMapMemory(device_, b.memory, 0, bytes, 0, &p));
    if (data)
      std::memcpy(p, data, bytes);
    else
      std::memset(p, 0, bytes);
    vkUnmapMemory(device_, b.memory);
    buffers_.push_back(b);
    return static_cast<int>(buffers_.size() - 1);
  }

  std::vector<float> read(int index) {
    const Buffer& b = buffers_[index];
    std::vector<float> out(b.size / 4);
    void* p = nullptr;
    VK_CHECK(vkMapMemory(device_, b.memory, 0, b.size, 0, &p));
    std::memcpy(out.data(), p, b.size);
    vkUnmapMemory(device_, b.memory);
    return out;
  }

  // A sampled 3D image uploaded from `data`; returns its index.
  int image(VkFormat format, int w, int h, int d, const std::vector<std::uint8_t>& data) {
    Image img;
    VkImageCreateInfo ici{};
    ici.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
    ici.imageType = VK_IMAGE_TYPE_3D;
    ici.format = format;
    ici.extent = {static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(h),
                  static_cast<std::uint32_t>(d)};
    ici.mipLevels = ici.arrayLayers = 1;
    ici.samples = VK_SAMPLE_COUNT_1_BIT;
    ici.tiling = VK_IMAGE_TILING_OPTIMAL;
    ici.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    ici.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VK_CHECK(vkCreateImage(device_, &ici, nullptr, &img.image));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device_, img.image, &req);
    img.memory = allocate(req, 0);
    VK_CHECK(vkBindImageMemory(device_, img.image, img.memory, 0));
    const int staging = buffer(data.size(), data.data(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
    VkCommandBuffer cb = begin();
    barrier(cb, img.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = ici.extent;
    vkCmdCopyBufferToImage(cb, buffers_[staging].buffer, img.image,
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    barrier(cb, img.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    submit(cb);
    VkImageViewCreateInfo vci{};
    vci.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
    vci.image = img.image;
    vci.viewType = VK_IMAGE_VIEW_TYPE_3D;
    vci.format = format;
    vci.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VK_CHECK(vkCreateImageView(device_, &vci, nullptr, &img.view));
    images_.push_back(img);
    return static_cast<int>(images_.size() - 1);
  }

  // Runs `spirv` over `groups` work groups. Bindings 0, 1: storage buffers; 2, 3: images (combined
  // with the sampler, or separate with the sampler at binding 4).
  void run(const std::vector<std::uint32_t>& spirv, int in, int out, int img3, int img4,
           bool separateSampler, std::uint32_t groups) {
    std::vector<VkDescriptorSetLayoutBinding> b;
    const VkDescriptorType imageType = separateSampler ? VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE
                                                       : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    b.push_back({0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    b.push_back({1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    b.push_back({2, imageType, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    b.push_back({3, imageType, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    if (separateSampler) {
      b.push_back({4, VK_DESCRIPTOR_TYPE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    }
    VkDescriptorSetLayoutCreateInfo lci{};
    lci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
    lci.bindingCount = static_cast<std::uint32_t>(b.size());
    lci.pBindings = b.data();
    VkDescriptorSetLayout layout;
    VK_CHECK(vkCreateDescriptorSetLayout(device_, &lci, nullptr, &layout));
    const VkDescriptorPoolSize sizes[] = {
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2}, {imageType, 2}, {VK_DESCRIPTOR_TYPE_SAMPLER, 1}};
    VkDescriptorPoolCreateInfo dpci{};
    dpci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    dpci.maxSets = 1;
    dpci.poolSizeCount = 3;
    dpci.pPoolSizes = sizes;
    VkDescriptorPool dpool;
    VK_CHECK(vkCreateDescriptorPool(device_, &dpci, nullptr, &dpool));
    VkDescriptorSetAllocateInfo dai{};
    dai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
    dai.descriptorPool = dpool;
    dai.descriptorSetCount = 1;
    dai.pSetLayouts = &layout;
    VkDescriptorSet set;
    VK_CHECK(vkAllocateDescriptorSets(device_, &dai, &set));
    const VkDescriptorBufferInfo bufs[2] = {{buffers_[in].buffer, 0, VK_WHOLE_SIZE},
                                            {buffers_[out].buffer, 0, VK_WHOLE_SIZE}};
    const VkSampler sampler = separateSampler ? VK_NULL_HANDLE : sampler_;
    const VkDescriptorImageInfo imgs[2] = {
        {sampler, images_[img3].view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
        {sampler, images_[img4].view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}};
    const VkDescriptorImageInfo samp = {sampler_, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_UNDEFINED};
    std::vector<VkWriteDescriptorSet> writes;
    for (std::uint32_t k = 0; k < 4; ++k) {
      VkWriteDescriptorSet w{};
      w.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
      w.dstSet = set;
      w.dstBinding = k;
      w.descriptorCount = 1;
      w.descriptorType = k < 2 ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER : imageType;
      if (k < 2)
        w.pBufferInfo = &bufs[k];
      else
        w.pImageInfo = &imgs[k - 2];
      writes.push_back(w);
    }
    if (separateSampler) {
      VkWriteDescriptorSet w{};
      w.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
      w.dstSet = set;
      w.dstBinding = 4;
      w.descriptorCount = 1;
      w.descriptorType = VK_DESCRIPTOR_TYPE_SAMPLER;
      w.pImageInfo = &samp;
      writes.push_back(w);
    }
    vkUpdateDescriptorSets(device_, static_cast<std::uint32_t>(writes.size()), writes.data(), 0,
                           nullptr);
    VkPipelineLayoutCreateInfo plci{};
    plci.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    plci.setLayoutCount = 1;
    plci.pSetLayouts = &layout;
    VkPipelineLayout playout;
    VK_CHECK(vkCreatePipelineLayout(device_, &plci, nullptr, &playout));
    VkShaderModuleCreateInfo smci{};
    smci.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
    smci.codeSize = spirv.size() * 4;
    smci.pCode = spirv.data();
    VkShaderModule module;
    VK_CHECK(vkCreateShaderModule(device_, &smci, nullptr, &module));
    VkComputePipelineCreateInfo cpci{};
    cpci.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
    cpci.stage = {};
    cpci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpci.stage.module = module;
    cpci.stage.pName = "main";
    cpci.layout = playout;
    VkPipeline pipeline;
    VK_CHECK(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &cpci, nullptr, &pipeline));
    VkCommandBuffer cb = begin();
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, playout, 0, 1, &set, 0, nullptr);
    vkCmdDispatch(cb, groups, 1, 1);
    submit(cb);
    vkDestroyPipeline(device_, pipeline, nullptr);
    vkDestroyShaderModule(device_, module, nullptr);
    vkDestroyPipelineLayout(device_, playout, nullptr);
    vkDestroyDescriptorPool(device_, dpool, nullptr);
    vkDestroyDescriptorSetLayout(device_, layout, nullptr);
  }

  std::string deviceName;
  std::uint32_t subTexelBits = 0;

 private:
  struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    std::size_t size = 0;
  };
  struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
  };

  VkDeviceMemory allocate(const VkMemoryRequirements& req, VkMemoryPropertyFlags flags) {
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(physical_, &mp);
    for (std::uint32_t i = 0; i < mp.memoryTypeCount; ++i) {
      if ((req.memoryTypeBits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & flags) == flags) {
        VkMemoryAllocateInfo mai{};
        mai.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
        mai.allocationSize = req.size;
        mai.memoryTypeIndex = i;
        VkDeviceMemory m;
        VK_CHECK(vkAllocateMemory(device_, &mai, nullptr, &m));
        return m;
      }
    }
    throw std::runtime_error("no suitable Vulkan memory type");
  }
  VkCommandBuffer begin() {
    VkCommandBufferAllocateInfo ai{};
    ai.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    ai.commandPool = pool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cb;
    VK_CHECK(vkAllocateCommandBuffers(device_, &ai, &cb));
    VkCommandBufferBeginInfo bi{};
    bi.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cb, &bi));
    return cb;
  }
  void submit(VkCommandBuffer cb) {
    VK_CHECK(vkEndCommandBuffer(cb));
    VkSubmitInfo si{};
    si.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    VK_CHECK(vkQueueSubmit(queue_, 1, &si, VK_NULL_HANDLE));
    VK_CHECK(vkQueueWaitIdle(queue_));
    vkFreeCommandBuffers(device_, pool_, 1, &cb);
  }
  void barrier(VkCommandBuffer cb, VkImage image, VkImageLayout from, VkImageLayout to) {
    VkImageMemoryBarrier b{};
    b.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    b.srcAccessMask = from == VK_IMAGE_LAYOUT_UNDEFINED ? 0 : VK_ACCESS_TRANSFER_WRITE_BIT;
    b.dstAccessMask = from == VK_IMAGE_LAYOUT_UNDEFINED ? VK_ACCESS_TRANSFER_WRITE_BIT
                                                        : VK_ACCESS_SHADER_READ_BIT;
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                         0, 0, nullptr, 0, nullptr, 1, &b);
  }

  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkSampler sampler_ = VK_NULL_HANDLE;
  std::uint32_t family_ = 0;
  std::vector<Buffer> buffers_;
  std::vector<Image> images_;
};

// ---- the C++ side ----
struct Reference {
  float s3, s4, cone, mb, closedForm;
  float spread3, spread4;  // D of the tolerance: texel range of the trilinear footprint(s)
};

// max - min of the 8 texels the trilinear filter reads at normalised coordinates (u, v, w).
float footprint(const gtbake::GtsoVolume& v, float cu, float cv, float cw) {
  const float c[3] = {cu, cv, cw};
  const int n[3] = {v.width, v.height, v.depth};
  int i0[3], i1[3];
  for (int a = 0; a < 3; ++a) {
    const float p = c[a] * static_cast<float>(n[a]) - 0.5f;
    const int i = static_cast<int>(std::floor(p));
    i0[a] = std::clamp(i, 0, n[a] - 1);
    i1[a] = std::clamp(i + 1, 0, n[a] - 1);
  }
  float lo = 1e30f, hi = -1e30f;
  for (int k = 0; k < 8; ++k) {
    const float t = gtbake::gtsoFetchTexel(v, k & 1 ? i1[0] : i0[0], k & 2 ? i1[1] : i0[1],
                                           k & 4 ? i1[2] : i0[2]);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  return hi - lo;
}

// The fixture's layouts (export_fixture.h) and its volumes' texture extents in them.
gtbake::GtsoLayout fixtureLayout(const std::vector<int>& axes) {
  return {{axes[0], axes[1], axes[2]}};
}
std::array<int, 3> volume3D() {
  const gtbake::GtsoLayout l = fixtureLayout(gtbake::test::kFixtureLayout3D);
  const int* n = gtbake::test::kFixture3D;
  return {n[l.axis[0]], n[l.axis[1]], n[l.axis[2]]};
}
std::array<int, 3> volume4D() {
  const gtbake::GtsoLayout l = fixtureLayout(gtbake::test::kFixtureLayout4D);
  const int* n = gtbake::test::kFixture4D;
  return {n[l.axis[0]], n[l.axis[1]], n[l.axis[2]] * n[3]};
}

Reference reference(const Exported& e, gtbake::GtsoTexelFormat format, const Input& p) {
  using namespace gtbake;
  const int* n3 = test::kFixture3D;
  const int* n4 = test::kFixture4D;
  const GtsoLayout l3 = fixtureLayout(test::kFixtureLayout3D);
  const GtsoLayout l4 = fixtureLayout(test::kFixtureLayout4D);
  const void* d3 = format == GtsoTexelFormat::kBc4 ? e.bc4[0].data() : e.r16[0].data();
  const void* d4 = format == GtsoTexelFormat::kBc4 ? e.bc4[1].data() : e.r16[1].data();
  const std::array<int, 3> e3 = volume3D(), e4 = volume4D();
  const GtsoVolume v3{format, d3, e3[0], e3[1], e3[2]};
  const GtsoVolume v4{format, d4, e4[0], e4[1], e4[2]};
  Reference r;
  r.s3 = gtso3DLookup(v3, n3, p.A, p.cosBeta, p.rp, l3);
  r.s4 = gtso4DLookup(v4, n4, p.A, p.cosBeta, p.rp, p.cosThetaO, l4);
  r.cone = gtsoConeModel(e.u, p.A, p.cosBeta, p.rp);
  r.mb = gtsoMultiBounce(e.coeffs, e.coeffs + 2, e.coeffs + 4, p.A, p.cosThetaO);
  r.closedForm = gtsoS3ClosedForm(e.closedForm, p.A, p.cosBeta, p.rp);
  const GtsoAxisT<float> a3 = gtso3DAxes(p.A, p.cosBeta, p.rp, n3);
  float c3[3];
  for (int k = 0; k < 3; ++k) c3[k] = gtsoTexelRemap(a3.t[k], n3[k]);
  r.spread3 = footprint(v3, c3[l3.axis[0]], c3[l3.axis[1]], c3[l3.axis[2]]);
  const GtsoAxisT<float> a4 = gtso4DAxes(p.A, p.cosBeta, p.rp, p.cosThetaO, n4);
  const float sw = a4.t[3] * static_cast<float>(n4[3] - 1);
  const int s0 = std::min(static_cast<int>(sw), n4[3] - 2);
  const int x = l4.axis[0], y = l4.axis[1], z = l4.axis[2];
  const float zin = a4.t[z] * static_cast<float>(n4[z] - 1) + 0.5f;
  const float depth = static_cast<float>(n4[z] * n4[3]);
  const float u = gtsoTexelRemap(a4.t[x], n4[x]), v = gtsoTexelRemap(a4.t[y], n4[y]);
  r.spread4 = std::max(footprint(v4, u, v, (static_cast<float>(s0 * n4[z]) + zin) / depth),
                       footprint(v4, u, v, (static_cast<float>((s0 + 1) * n4[z]) + zin) / depth));
  return r;
}

std::vector<Input> randomInputs() {
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f), u11(-1.0f, 1.0f);
  std::vector<Input> in(kPoints);
  for (Input& p : in) p = {u01(rng), u11(rng), u01(rng), u01(rng)};
  // A few exact corners: texel centres at the axis ends and the mirror limit.
  in[0] = {0.0f, 1.0f, 0.0f, 1.0f};
  in[1] = {1.0f, 0.0f, 1.0f, 0.0f};
  in[2] = {0.5f, 0.7f, 0.0f, 0.7f};
  return in;
}

// Sensitivity of the cone model to the device's trigonometry: Vulkan requires only 2^-11 absolute
// error of sin/cos, so each angle (alpha_v, alpha_s, beta) and each of the three acos arguments of
// the lens formula is perturbed by +-2^-11 (central differences in float); tolerance = 1e-4 + the
// sum of the six largest changes of S.
float coneTolerance(const Input& p, float u) {
  using namespace gtbake;
  const float alpha = p.rp * p.rp;
  const float omc = gtsoOneMinusExp(0.5f * alpha * alpha * std::log(u));
  if (omc <= 0.0f) return 1e-4f;
  const float av = gtsoAlphaV(p.A), as = 2.0f * std::asin(std::sqrt(0.5f * omc));
  const float beta = gtsoAcos(p.cosBeta);
  const float h = std::ldexp(1.0f, -11);
  const float pi = static_cast<float>(kGtsoPi);
  // S with the three acos arguments of the partial-overlap case shifted by dx[k].
  auto S = [&](float a1, float a2, float b, const float* dx) {
    a1 = std::max(a1, 0.0f);
    float omega;
    if (b >= a1 + a2) {
      omega = 0.0f;
    } else if (b <= std::fabs(a1 - a2)) {
      omega = gtsoCapIntersection(a1, a2, b);
    } else {
      const float c1 = std::cos(a1), c2 = std::cos(a2), cd = std::cos(b);
      const float s1 = std::sin(a1), s2 = std::sin(a2), sd = std::sin(b);
      const float t0 = gtsoAcos((cd - c1 * c2) / (s1 * s2) + dx[0]);
      const float t1 = gtsoAcos((c2 - cd * c1) / (sd * s1) + dx[1]);
      const float t2 = gtsoAcos((c1 - cd * c2) / (sd * s2) + dx[2]);
      omega = std::max(0.0f, 2.0f * (pi - t0 - c1 * t1 - c2 * t2));
    }
    const float sh = std::sin(0.5f * a2);
    return sh > 0.0f ? gtsoClamp01(omega / (4.0f * pi * sh * sh)) : 0.0f;
  };
  const float zero[3] = {0.0f, 0.0f, 0.0f};
  const float s0 = S(av, as, beta, zero);
  float t = 1e-4f;
  auto add = [&](float plus, float minus) {
    t += std::max(std::fabs(plus - s0), std::fabs(minus - s0));
  };
  add(S(av + h, as, beta, zero), S(av - h, as, beta, zero));
  add(S(av, as + h, beta, zero), S(av, std::max(as - h, 0.5f * as), beta, zero));
  add(S(av, as, beta + h, zero), S(av, as, beta - h, zero));
  for (int k = 0; k < 3; ++k) {
    float up[3] = {0.0f, 0.0f, 0.0f}, down[3] = {0.0f, 0.0f, 0.0f};
    up[k] = h;
    down[k] = -h;
    add(S(av, as, beta, up), S(av, as, beta, down));
  }
  return t;
}

// Sensitivity of the closed-form S3 to the device's float arithmetic. The shader and the C++
// header evaluate the same float operations, but the device may contract multiply-adds, sum in
// another order and has looser exp/log (Vulkan: exp 3 + 2|x| ULP, log 3 ULP or 2^-21 absolute).
// These are bounded as errors of the function's intermediate values: each of the nine
// polynomials P_s off by 2^-19 of the sum of its terms' magnitudes (ten float products and sums,
// plus the exp that reads it), the median u_m and the log-odds u each off by
// 2^-20 (1 + |value|) (their log). Tolerance = 1e-4 + the sum of the function's largest changes
// under each shift (double precision, both signs). Near the mirror step for r_p -> 0 the slope in
// u reaches sin(2 theta_o)/(2e-4), and the tolerance grows with it: that is the function's
// conditioning (a float input there is uncertain by as much), not slack.
float closedFormTolerance(const Input& in, const float* kf) {
  using namespace gtbake;
  constexpr int kB = kGtsoS3ClosedFormBasis;
  double k[kGtsoS3ClosedFormCoeffs];
  for (int i = 0; i < kGtsoS3ClosedFormCoeffs; ++i) k[i] = kf[i];
  const double A = in.A, cb = in.cosBeta, rp = in.rp;
  if (!(A > 0.0) || !(A < 1.0)) return 1e-4f;  // exact 0 and 1 on both sides
  const double mu = gtsoClamp01(cb), r = gtsoClamp01(rp);
  const double alpha = r * r + kGtsoS3ClosedFormAlphaFloor;
  const double h = mu * std::sqrt(1.0 - mu * mu) / alpha;
  double b[kB];
  gtsoS3ClosedFormBasis(std::sqrt(mu), r, h / (1.0 + h), b);
  const double s0 = gtsoS3ClosedForm(k, A, cb, rp);
  double tol = 1e-4;
  auto change = [&](double* kk) { return std::fabs(gtsoS3ClosedForm(kk, A, cb, rp) - s0); };
  for (int s = 0; s < kGtsoS3ClosedFormSets; ++s) {
    double mag = 0.0;
    for (int i = 0; i < kB; ++i) mag += std::fabs(k[s * kB + i] * b[i]);
    const double eps = std::ldexp(mag, -19);
    double worst = 0.0;
    for (double sign : {-1.0, 1.0}) {
      k[s * kB] += sign * eps;  // basis term 0 is 1: shifts P_s by eps
      worst = std::max(worst, change(k));
      k[s * kB] -= sign * eps;
    }
    tol += worst;
  }
  // The median through P_c (u_m += alpha P_c), and u through A (du/dA = 1 / (2 A (1 - A))).
  const GtsoS3ClosedFormLobe<double> lobe = gtsoS3ClosedFormLobe(k, cb, rp);
  const double dm = std::ldexp(1.0 + std::fabs(lobe.median), -20);
  double worstM = 0.0, worstU = 0.0;
  const double u = 0.5 * std::log(A / (1.0 - A));
  const double du = std::ldexp(1.0 + std::fabs(u), -20);
  for (double sign : {-1.0, 1.0}) {
    k[2 * kB] += sign * dm / alpha;
    worstM = std::max(worstM, change(k));
    k[2 * kB] -= sign * dm / alpha;
    const double A2 = 1.0 / (1.0 + std::exp(-2.0 * (u + sign * du)));
    worstU = std::max(worstU, std::fabs(gtsoS3ClosedForm(k, A2, cb, rp) - s0));
  }
  return static_cast<float>(tol + worstM + worstU);
}

class ShaderExec : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { exported_ = new Exported(exportFixture()); }
  static void TearDownTestSuite() {
    fs::remove_all(exported_->dir);
    delete exported_;
  }

  // Runs one language with textures of one format and compares every output.
  void check(bool hlsl, gtbake::GtsoTexelFormat format) {
    Vulkan vk;
    const Exported& e = *exported_;
    const VkFormat vkFormat =
        format == gtbake::GtsoTexelFormat::kBc4 ? VK_FORMAT_BC4_UNORM_BLOCK : VK_FORMAT_R16_UNORM;
    if (!vk.samples3D(vkFormat)) {
      ASSERT_NE(vkFormat, VK_FORMAT_R16_UNORM) << vk.deviceName << " cannot sample R16 volumes";
      GTEST_SKIP() << vk.deviceName << " does not sample 3D BC4 images (R16 is checked)";
    }
    EXPECT_GE(vk.subTexelBits, 8u) << "the tolerance assumes 8 sub-texel bits";
    const std::string source =
        hlsl ? e.hlsl + kHlslMain : std::string("#version 450\n") + e.glsl + kGlslMain;
    const std::vector<std::uint32_t> spirv = compile(e.dir, source, hlsl);
    const std::vector<Input> in = randomInputs();
    const int inBuf =
        vk.buffer(in.size() * sizeof(Input), in.data(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    const int outBuf = vk.buffer(in.size() * 32, nullptr, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    const std::array<int, 3> n3 = volume3D(), n4 = volume4D();  // texture extents
    const bool bc4 = format == gtbake::GtsoTexelFormat::kBc4;
    const int img3 = vk.image(vkFormat, n3[0], n3[1], n3[2], bc4 ? e.bc4[0] : e.r16[0]);
    const int img4 = vk.image(vkFormat, n4[0], n4[1], n4[2], bc4 ? e.bc4[1] : e.r16[1]);
    vk.run(spirv, inBuf, outBuf, img3, img4, hlsl, kPoints / kLocalSize);
    const std::vector<float> out = vk.read(outBuf);
    float worst[5] = {0, 0, 0, 0, 0}, worstRatio = 0.0f;
    int failures = 0;
    for (int i = 0; i < kPoints; ++i) {
      const Reference r = reference(e, format, in[i]);
      const float got[5] = {out[8 * i], out[8 * i + 1], out[8 * i + 2], out[8 * i + 3],
                            out[8 * i + 4]};
      const float want[5] = {r.s3, r.s4, r.cone, r.mb, r.closedForm};
      const float decode = bc4 ? kBc4DecodeTolerance : 0.0f;
      const float tol[5] = {r.spread3 * kFilterTolerance + decode + 2e-6f,
                            r.spread4 * kFilterTolerance + decode + 2e-6f,
                            coneTolerance(in[i], e.u), 1e-5f,
                            closedFormTolerance(in[i], e.closedForm)};
      for (int k = 0; k < 5; ++k) {
        const float d = std::fabs(got[k] - want[k]);
        worst[k] = std::max(worst[k], d);
        worstRatio = std::max(worstRatio, d / tol[k]);
        if (!(d <= tol[k]) && failures++ < 10) {
          ADD_FAILURE() << (hlsl ? "HLSL" : "GLSL") << " output " << k << " at A " << in[i].A
                        << " cosBeta " << in[i].cosBeta << " rp " << in[i].rp << " cosThetaO "
                        << in[i].cosThetaO << ": shader " << got[k] << ", C++ " << want[k]
                        << ", tolerance " << tol[k];
        }
      }
    }
    std::printf(
        "%s on %s, %s textures, %d points: max |shader - C++| S3 %.2e S4 %.2e cone %.2e "
        "multi-bounce %.2e closed-form S3 %.2e; worst error / tolerance %.3f\n",
        hlsl ? "HLSL" : "GLSL", vk.deviceName.c_str(), bc4 ? "BC4" : "R16", kPoints, worst[0],
        worst[1], worst[2], worst[3], worst[4], worstRatio);
    EXPECT_EQ(failures, 0);
  }

  static Exported* exported_;
};
Exported* ShaderExec::exported_ = nullptr;

TEST_F(ShaderExec, GlslR16) {
  check(false, gtbake::GtsoTexelFormat::kR16);
}
TEST_F(ShaderExec, HlslR16) {
  check(true, gtbake::GtsoTexelFormat::kR16);
}
TEST_F(ShaderExec, GlslBc4) {
  check(false, gtbake::GtsoTexelFormat::kBc4);
}
TEST_F(ShaderExec, HlslBc4) {
  check(true, gtbake::GtsoTexelFormat::kBc4);
}

}  // namespace
