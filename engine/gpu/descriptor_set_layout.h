#pragma once
// Descriptor set layouts, made in one place: the shader statistics device (shader_statistics.h)
// gets a copy of every layout a pipeline may use, so each one is created through this.
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace engine::gpu {

class Context;

struct DescriptorSetLayoutDesc {
  std::string name;  // for validation messages and debuggers
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  std::vector<VkDescriptorBindingFlags> bindingFlags;  // empty, or one per binding
};

class DescriptorSetLayout {
 public:
  DescriptorSetLayout() = default;
  // Throws VulkanError naming the call when the driver refuses (checked-call convention, vk_check.h).
  DescriptorSetLayout(const Context& context, const DescriptorSetLayoutDesc& desc);
  ~DescriptorSetLayout();
  DescriptorSetLayout(DescriptorSetLayout&& other) noexcept;
  DescriptorSetLayout& operator=(DescriptorSetLayout&& other) noexcept;
  DescriptorSetLayout(const DescriptorSetLayout&) = delete;
  DescriptorSetLayout& operator=(const DescriptorSetLayout&) = delete;

  VkDescriptorSetLayout handle() const { return layout_; }

 private:
  void destroy() noexcept;
  const Context* context_ = nullptr;
  VkDescriptorSetLayout layout_ = VK_NULL_HANDLE;
};

}  // namespace engine::gpu
