#include "render/sphere_trace_textures.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "engine/gpu/context.h"
#include "engine/gpu/descriptor_set_layout.h"
#include "engine/gpu/image_sampler_sets.h"
#include "engine/gpu/vk_check.h"
#include "hermite_sdf/core/cells.h"

namespace hsdf {

using engine::Expected;
using engine::Status;

VkFormat fieldTextureFormat(TraceMethod method, bool halfPrecision) {
  if (method == TraceMethod::Trilinear) return halfPrecision ? VK_FORMAT_R16_SFLOAT : VK_FORMAT_R32_SFLOAT;
  return halfPrecision ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT;
}

namespace {

template <class T>
void appendScalar(std::vector<std::uint8_t>& bytes, T value) {
  std::uint8_t raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  bytes.insert(bytes.end(), raw, raw + sizeof(T));
}

void appendValue(std::vector<std::uint8_t>& bytes, float value, bool halfPrecision) {
  if (halfPrecision)
    appendScalar(bytes, floatToHalf(value));
  else
    appendScalar(bytes, value);
}

}  // namespace

Expected<FieldTexels> packFieldTexels(const HermiteField& field, TraceMethod method, bool halfPrecision) {
  ENGINE_TRY(validateGrid(field.grid));
  if (field.samples.size() != field.grid.sampleCount())
    return engine::makeError("field has " + std::to_string(field.samples.size()) + " samples, its grid needs " +
                             std::to_string(field.grid.sampleCount()));
  FieldTexels texels;
  texels.format = fieldTextureFormat(method, halfPrecision);
  const std::size_t scalars = method == TraceMethod::Trilinear ? 1 : 4;
  texels.bytes.reserve(field.samples.size() * scalars * (halfPrecision ? 2 : 4));
  for (const HermiteSample& s : field.samples) {
    appendValue(texels.bytes, s.f, halfPrecision);
    if (method == TraceMethod::Trilinear) continue;
    appendValue(texels.bytes, s.fx, halfPrecision);
    appendValue(texels.bytes, s.fy, halfPrecision);
    appendValue(texels.bytes, s.fz, halfPrecision);
  }
  return texels;
}

Status checkFieldFormats(const engine::gpu::Context& context) {
  for (const TraceMethod method : {TraceMethod::Trilinear, TraceMethod::Hermite}) {
    for (const bool half : {false, true}) {
      const VkFormat format = fieldTextureFormat(method, half);
      VkFormatProperties properties{};
      vkGetPhysicalDeviceFormatProperties(context.physicalDevice(), format, &properties);
      VkFormatFeatureFlags needed = VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT | VK_FORMAT_FEATURE_TRANSFER_DST_BIT;
      if (method == TraceMethod::Trilinear) needed |= VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
      if ((properties.optimalTilingFeatures & needed) != needed)
        return engine::makeError("the device cannot sample" +
                                 std::string(method == TraceMethod::Trilinear ? " (with linear filtering)" : "") +
                                 " 3D textures of format " + std::to_string(int(format)));
    }
  }
  return {};
}

namespace {

// Slot numbers handed out and taken back; freed numbers are reused first.
class SlotAllocator {
 public:
  std::uint32_t acquire() {
    if (free_.empty()) return next_++;
    const std::uint32_t slot = free_.back();
    free_.pop_back();
    return slot;
  }
  void release(std::uint32_t slot) { free_.push_back(slot); }

 private:
  std::vector<std::uint32_t> free_;
  std::uint32_t next_ = 0;
};

// Descriptor indexing: one set holding an array of combined image samplers; shaders index it with
// SphereTraceDraw::texture, so all objects of a pass draw with one bind.
class BindlessTable final : public FieldTextureBindings {
 public:
  explicit BindlessTable(const engine::gpu::Context& context) : context_(context) {}
  ~BindlessTable() override {
    vkDestroyDescriptorPool(context_.device(), pool_, nullptr);
  }

  Status create() {
    capacity_ = tableCapacity();
    // Slots that no texture occupies stay unwritten: allowed because no draw indexes them.
    layout_ = engine::gpu::DescriptorSetLayout(
        context_, {"sphere trace bindless layout",
                   {{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, capacity_, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}},
                   {VK_DESCRIPTOR_BINDING_PARTIALLY_BOUND_BIT}});

    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, capacity_};
    VkDescriptorPoolCreateInfo poolInfo{};
    poolInfo.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &size;
    VK_TRY(vkCreateDescriptorPool(context_.device(), &poolInfo, nullptr, &pool_));
    context_.setName(pool_, VK_OBJECT_TYPE_DESCRIPTOR_POOL, "sphere trace bindless pool");
    VkDescriptorSetAllocateInfo allocInfo{};
    allocInfo.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
    allocInfo.descriptorPool = pool_;
    allocInfo.descriptorSetCount = 1;
    const VkDescriptorSetLayout setLayout = layout_.handle();
    allocInfo.pSetLayouts = &setLayout;
    VK_TRY(vkAllocateDescriptorSets(context_.device(), &allocInfo, &set_));
    context_.setName(set_, VK_OBJECT_TYPE_DESCRIPTOR_SET, "sphere trace bindless textures");
    return {};
  }

  bool bindless() const override { return true; }
  VkDescriptorSetLayout layout() const override { return layout_.handle(); }

  Expected<std::uint32_t> add(VkImageView view, VkSampler sampler) override {
    const std::uint32_t slot = slots_.acquire();
    if (slot >= capacity_) {
      slots_.release(slot);
      return engine::makeError("bindless field texture table is full (" + std::to_string(capacity_) + " textures)");
    }
    // Without update-after-bind, a set that pending frames have bound must not be written.
    context_.waitIdle();
    const VkDescriptorImageInfo image{sampler, view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    const VkWriteDescriptorSet write = engine::gpu::combinedImageSamplerWrite(set_, 0, slot, image);
    vkUpdateDescriptorSets(context_.device(), 1, &write, 0, nullptr);
    return slot;
  }

  // The slot's descriptor stays in the table (allowed by PARTIALLY_BOUND: no draw indexes it, and
  // only descriptors a draw uses must stay valid); the caller destroys the image next.
  void remove(std::uint32_t slot) override { slots_.release(slot); }

  void bind(VkCommandBuffer cmd, VkPipelineLayout layout, std::uint32_t) const override {
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 1, 1, &set_, 0, nullptr);
  }

 private:
  // Combined image samplers count against the sampler and the sampled-image limits; the scene
  // set (set 0) uses two of each in the fragment stage, and attachments count as resources: keep
  // a margin of 8.
  std::uint32_t tableCapacity() const {
    VkPhysicalDeviceProperties properties{};
    vkGetPhysicalDeviceProperties(context_.physicalDevice(), &properties);
    const VkPhysicalDeviceLimits& l = properties.limits;
    const std::uint32_t limit = std::min({l.maxPerStageDescriptorSampledImages, l.maxPerStageDescriptorSamplers,
                                          l.maxDescriptorSetSampledImages, l.maxDescriptorSetSamplers,
                                          l.maxPerStageResources});
    return std::clamp(limit, 9u, 4104u) - 8u;
  }

  const engine::gpu::Context& context_;
  engine::gpu::DescriptorSetLayout layout_;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  std::uint32_t capacity_ = 0;
  SlotAllocator slots_;
};

// No descriptor indexing: one set (one combined image sampler) per texture, bound before each
// draw that uses it (engine::gpu::ImageSamplerSets), kept by slot.
class PerTextureSets final : public FieldTextureBindings {
 public:
  explicit PerTextureSets(const engine::gpu::Context& context)
      : sets_(context, VK_SHADER_STAGE_FRAGMENT_BIT, 1, "sphere trace field texture") {}

  bool bindless() const override { return false; }
  VkDescriptorSetLayout layout() const override { return sets_.layout(); }

  Expected<std::uint32_t> add(VkImageView view, VkSampler sampler) override {
    const VkDescriptorImageInfo image{sampler, view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    ENGINE_TRY_ASSIGN(const engine::gpu::ImageSamplerSets::Set set, sets_.add({&image, 1}));
    const std::uint32_t slot = slots_.acquire();
    if (slot >= entries_.size()) entries_.resize(slot + 1);
    entries_[slot] = set;
    return slot;
  }

  void remove(std::uint32_t slot) override {
    sets_.remove(entries_.at(slot));
    entries_.at(slot) = {};
    slots_.release(slot);
  }

  void bind(VkCommandBuffer cmd, VkPipelineLayout layout, std::uint32_t slot) const override {
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 1, 1, &entries_.at(slot).set, 0, nullptr);
  }

 private:
  engine::gpu::ImageSamplerSets sets_;
  std::vector<engine::gpu::ImageSamplerSets::Set> entries_;  // by slot
  SlotAllocator slots_;
};

}  // namespace

Expected<std::unique_ptr<FieldTextureBindings>> FieldTextureBindings::create(const engine::gpu::Context& context,
                                                                            bool bindless) {
  if (bindless && !context.capabilities().descriptorIndexing)
    return engine::makeError("bindless field textures need descriptor indexing, which " +
                             context.capabilities().deviceName + " lacks");
  if (bindless) {
    auto table = std::make_unique<BindlessTable>(context);
    ENGINE_TRY(table->create());
    return std::unique_ptr<FieldTextureBindings>(std::move(table));
  }
  return std::unique_ptr<FieldTextureBindings>(std::make_unique<PerTextureSets>(context));
}

}  // namespace hsdf
