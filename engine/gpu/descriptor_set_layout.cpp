#include "engine/gpu/descriptor_set_layout.h"

#include <stdexcept>
#include <utility>

#include "engine/gpu/context.h"
#include "engine/gpu/shader_statistics.h"
#include "engine/gpu/vk_check.h"

namespace engine::gpu {

DescriptorSetLayout::DescriptorSetLayout(const Context& context, const DescriptorSetLayoutDesc& desc)
    : context_(&context) {
  if (!desc.bindingFlags.empty() && desc.bindingFlags.size() != desc.bindings.size())
    throw std::invalid_argument("descriptor set layout '" + desc.name + "': " + std::to_string(desc.bindingFlags.size()) +
                                " binding flags for " + std::to_string(desc.bindings.size()) + " bindings");
  VkDescriptorSetLayoutBindingFlagsCreateInfo flags{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_BINDING_FLAGS_CREATE_INFO};
  flags.bindingCount = static_cast<std::uint32_t>(desc.bindingFlags.size());
  flags.pBindingFlags = desc.bindingFlags.data();
  VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  info.pNext = desc.bindingFlags.empty() ? nullptr : &flags;
  info.bindingCount = static_cast<std::uint32_t>(desc.bindings.size());
  info.pBindings = desc.bindings.data();
  try {  // a constructor that throws runs no destructor; an injected fault leaves a created layout
    VK_CHECK(vkCreateDescriptorSetLayout(context.device(), &info, nullptr, &layout_));
  } catch (...) {
    destroy();
    throw;
  }
  context.setName(layout_, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, desc.name);
  if (ShaderStatistics* statistics = context.shaderStatistics()) {
    if (const Status copied = statistics->addSetLayout(layout_, info); !copied) {
      destroy();
      throw std::runtime_error("descriptor set layout '" + desc.name + "': " + copied.error().message);
    }
  }
}

DescriptorSetLayout::~DescriptorSetLayout() { destroy(); }

DescriptorSetLayout::DescriptorSetLayout(DescriptorSetLayout&& other) noexcept { *this = std::move(other); }

DescriptorSetLayout& DescriptorSetLayout::operator=(DescriptorSetLayout&& other) noexcept {
  if (this != &other) {
    destroy();
    context_ = std::exchange(other.context_, nullptr);
    layout_ = std::exchange(other.layout_, VK_NULL_HANDLE);
  }
  return *this;
}

void DescriptorSetLayout::destroy() noexcept {
  if (!layout_) return;
  if (ShaderStatistics* statistics = context_->shaderStatistics()) statistics->removeSetLayout(layout_);
  vkDestroyDescriptorSetLayout(context_->device(), layout_, nullptr);
  layout_ = VK_NULL_HANDLE;
}

}  // namespace engine::gpu
