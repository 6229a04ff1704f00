#pragma once
// The difference view of the split-screen comparison: per pixel, the angle between the normals two
// methods give the same surface, from two frames drawn with DEBUG_VIEW_NORMALS (colour 0.5 n + 0.5,
// sRGB-encoded 8-bit: the angle resolution is about 1 degree; identical images give exactly 0),
// plus the pixels that one method covers and the other does not. Computed on the CPU from the
// read-back frames (a diagnostic view: two extra frames and two read-backs per shown frame), shown
// as a heat map copied over the frame by an OverlayPass, before the UI.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/gpu/buffer.h"
#include "engine/render/renderer.h"

namespace samples {

struct NormalDifference {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  // Per pixel (row-major from the top): the angle in degrees where both methods cover the pixel,
  // -1 where only one does, -2 where neither does.
  std::vector<float> degrees;
  std::uint64_t coveredBoth = 0;
  std::uint64_t coveredEither = 0;
  std::uint64_t coverageDiffers = 0;  // covered by exactly one method
  double meanDegrees = 0.0;           // over the pixels both cover
  double maxDegrees = 0.0;
  // Share of the pixels either method covers that only one covers (0 when nothing is covered).
  double coverageDiffersShare() const {
    return coveredEither ? double(coverageDiffers) / double(coveredEither) : 0.0;
  }
};

// A frame read back for the comparison: RGBA8 sRGB colour of the normals view and the visibility
// ids (x != 0: covered).
struct NormalsFrame {
  std::vector<std::uint8_t> rgba;
  std::vector<glm::uvec2> visibility;
};

// Errors: the two frames (or a frame and the size) disagree in size.
engine::Expected<NormalDifference> compareNormals(const NormalsFrame& a, const NormalsFrame& b, std::uint32_t width,
                                                  std::uint32_t height);

// The heat map as RGBA8 bytes for an sRGB target: 0 degrees blue, rangeDegrees (and more) red,
// pixels covered by one method only white, background dark grey.
std::vector<std::uint8_t> heatMapImage(const NormalDifference& difference, float rangeDegrees);
// The colour of `degrees` on the heat map (linear RGB), for the legend.
glm::vec3 heatColor(float degrees, float rangeDegrees);

// Copies an RGBA8 image over the frame's colour target (same size), then runs `next` (the UI).
class ImageOverlay final : public engine::render::OverlayPass {
 public:
  ImageOverlay(const engine::gpu::Context& context, std::uint32_t framesInFlight);
  // The image of the next frames; a size other than the frame's is not drawn.
  void setImage(std::vector<std::uint8_t> rgba, std::uint32_t width, std::uint32_t height);
  void setNext(engine::render::OverlayPass* next) { next_ = next; }
  void record(VkCommandBuffer cmd, const engine::gpu::Image& color, std::uint32_t frameSlot) override;

 private:
  const engine::gpu::Context& context_;
  std::vector<engine::gpu::Buffer> staging_;  // per frame in flight
  std::vector<std::uint8_t> rgba_;
  std::uint32_t width_ = 0, height_ = 0;
  engine::render::OverlayPass* next_ = nullptr;
};

}  // namespace samples
