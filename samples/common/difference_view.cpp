#include "difference_view.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "engine/gpu/context.h"
#include "engine/gpu/image.h"

namespace samples {
namespace {

constexpr float kOnlyOne = -1.0f;
constexpr float kNeither = -2.0f;

float srgbToLinear(std::uint8_t value) {
  const float c = float(value) / 255.0f;
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

std::uint8_t linearToSrgb(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
  return std::uint8_t(std::lround(s * 255.0f));
}

// DEBUG_VIEW_NORMALS writes 0.5 n + 0.5 (linear) into the sRGB target.
glm::vec3 decodeNormal(const std::uint8_t* rgba) {
  const glm::vec3 v(srgbToLinear(rgba[0]), srgbToLinear(rgba[1]), srgbToLinear(rgba[2]));
  const glm::vec3 n = 2.0f * v - 1.0f;
  const float length = glm::length(n);
  return length > 0.0f ? n / length : glm::vec3(0.0f, 0.0f, 1.0f);
}

}  // namespace

engine::Expected<NormalDifference> compareNormals(const NormalsFrame& a, const NormalsFrame& b, std::uint32_t width,
                                                  std::uint32_t height) {
  const std::size_t pixels = std::size_t(width) * height;
  for (const NormalsFrame* frame : {&a, &b})
    if (frame->rgba.size() != pixels * 4 || frame->visibility.size() != pixels)
      return engine::makeError(fmt::format("difference view: a frame of {} colour bytes and {} ids is not {}x{}",
                                           frame->rgba.size(), frame->visibility.size(), width, height));
  NormalDifference d;
  d.width = width;
  d.height = height;
  d.degrees.assign(pixels, kNeither);
  double sum = 0.0;
  for (std::size_t i = 0; i < pixels; ++i) {
    const bool inA = a.visibility[i].x != 0, inB = b.visibility[i].x != 0;
    if (!inA && !inB) continue;
    ++d.coveredEither;
    if (inA != inB) {
      ++d.coverageDiffers;
      d.degrees[i] = kOnlyOne;
      continue;
    }
    ++d.coveredBoth;
    // Identical bytes are 0 exactly (acos of a rounded dot product would give ~0.02 degrees).
    const bool same = std::equal(&a.rgba[4 * i], &a.rgba[4 * i + 3], &b.rgba[4 * i]);
    const float cosine = glm::dot(decodeNormal(&a.rgba[4 * i]), decodeNormal(&b.rgba[4 * i]));
    const float degrees = same ? 0.0f : glm::degrees(std::acos(std::clamp(cosine, -1.0f, 1.0f)));
    d.degrees[i] = degrees;
    sum += double(degrees);
    d.maxDegrees = std::max(d.maxDegrees, double(degrees));
  }
  d.meanDegrees = d.coveredBoth ? sum / double(d.coveredBoth) : 0.0;
  return d;
}

// The shaders' heat() (shaders/shared/debug_colors.glsl).
glm::vec3 heatColor(float degrees, float rangeDegrees) {
  const float x = std::clamp(degrees / std::max(rangeDegrees, 1e-6f), 0.0f, 1.0f);
  return glm::clamp(glm::vec3(2.0f * x - 0.5f, 1.0f - std::abs(2.0f * x - 1.0f), 1.5f - 2.0f * x), 0.0f, 1.0f);
}

std::vector<std::uint8_t> heatMapImage(const NormalDifference& d, float rangeDegrees) {
  std::vector<std::uint8_t> rgba(d.degrees.size() * 4, 255);
  for (std::size_t i = 0; i < d.degrees.size(); ++i) {
    glm::vec3 color(0.02f);                   // neither: background
    if (d.degrees[i] == kOnlyOne) color = glm::vec3(1.0f);  // coverage differs
    else if (d.degrees[i] >= 0.0f) color = heatColor(d.degrees[i], rangeDegrees);
    for (int c = 0; c < 3; ++c) rgba[4 * i + std::size_t(c)] = linearToSrgb(color[c]);
  }
  return rgba;
}

ImageOverlay::ImageOverlay(const engine::gpu::Context& context, std::uint32_t framesInFlight)
    : context_(context), staging_(framesInFlight) {}

void ImageOverlay::setImage(std::vector<std::uint8_t> rgba, std::uint32_t width, std::uint32_t height) {
  rgba_ = std::move(rgba);
  width_ = width;
  height_ = height;
}

// The colour target arrives and leaves in COLOR_ATTACHMENT_OPTIMAL (the UI pass draws on it next).
void ImageOverlay::record(VkCommandBuffer cmd, const engine::gpu::Image& color, std::uint32_t frameSlot) {
  const VkExtent3D extent = color.extent();
  const bool fits = extent.width == width_ && extent.height == height_ && !rgba_.empty() &&
                    color.format() == VK_FORMAT_R8G8B8A8_SRGB && frameSlot < staging_.size();
  if (fits) {
    engine::gpu::Buffer& staging = staging_[frameSlot];
    if (!staging || staging.size() != rgba_.size())  // this slot's last frame is complete (fence)
      staging = engine::gpu::Buffer(context_, rgba_.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                    engine::gpu::MemoryUsage::Upload, "difference view heat map");
    staging.write(rgba_.data(), rgba_.size());
    engine::gpu::imageBarrier(cmd, color.handle(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                              VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                              VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                              VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {width_, height_, 1};
    vkCmdCopyBufferToImage(cmd, staging.handle(), color.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    engine::gpu::imageBarrier(cmd, color.handle(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                              VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT,
                              VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                              VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT);
  }
  if (next_) next_->record(cmd, color, frameSlot);
}

}  // namespace samples
