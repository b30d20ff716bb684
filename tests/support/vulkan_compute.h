// A minimal Vulkan compute harness for the shader tests: one CPU device (lavapipe), storage
// buffers, sampled 3D images and one compute dispatch, plus the glslangValidator call that turns
// GLSL or HLSL into SPIR-V. Header-only; errors throw std::runtime_error.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/atomic_file.h"

#define VK_CHECK(call)                                                                      \
  do {                                                                                      \
    const VkResult r_ = (call);                                                             \
    if (r_ != VK_SUCCESS) throw std::runtime_error(#call " failed: " + std::to_string(r_)); \
  } while (0)

namespace gtbake::test {

// Compiles a compute shader (GLSL, or HLSL with entry point main) to SPIR-V with the
// glslangValidator at `glslang`, in `dir`; throws with the compiler's log on failure.
inline std::vector<std::uint32_t> compileShader(const std::string& glslang,
                                                const std::filesystem::path& dir,
                                                const std::string& source, bool hlsl) {
  namespace fs = std::filesystem;
  const fs::path src = dir / (hlsl ? "main.hlsl" : "main.comp");
  const fs::path spv = dir / (hlsl ? "hlsl.spv" : "glsl.spv");
  std::ofstream(src) << source;
  const std::string cmd = glslang + " -V " + (hlsl ? "-D -e main -S comp " : "-S comp ") +
                          src.string() + " -o " + spv.string() + " > " +
                          (dir / "glslang.log").string() + " 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    throw std::runtime_error("glslangValidator failed:\n" + gtbake::readFile(dir / "glslang.log"));
  }
  const std::string bytes = gtbake::readFile(spv);
  std::vector<std::uint32_t> words(bytes.size() / 4);
  std::memcpy(words.data(), bytes.data(), words.size() * 4);
  return words;
}

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

}  // namespace gtbake::test
