// The mesh textures (engine/render/mesh_textures.h): every material's textures in a descriptor set
// of its own (engine/gpu/image_sampler_sets.h), the sets drawn from pools of 64.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/render/components.h"
#include "engine/scene/scene_data.h"
#include "gpu_test_support.h"

namespace {

using namespace engine;
using gputest::Frame;

class MeshTexturesTest : public gputest::GpuTest {};

// A colour of its own for texture i (sRGB), unlike any other of the first 256.
glm::u8vec4 textureColor(std::uint32_t i) {
  return {std::uint8_t(20 + 23 * (i % 10)), std::uint8_t(20 + 29 * ((i / 10) % 8)), std::uint8_t(40 + 2 * i), 255};
}

// Why: a scene with more textures than one descriptor pool holds (64) draws each mesh with its own
// texture. Tricky because the sets past the first pool come from a pool made on demand, and a set
// written with another texture's image, or bound from the wrong entry, still draws a plausible
// colour: every square is a 1 x 1 texture of a colour of its own on a white material, lit alike
// (one normal, an orthographic-like narrow view: the same light on each), so each square's centre
// pixel must be its own texel times the same lighting, compared with the CPU reference.
TEST_F(MeshTexturesTest, MoreTexturesThanAPoolHoldsEachDrawOnItsOwnMesh) {
  const std::uint32_t columns = 10, rows = 8, size = 160;
  createRenderer(size, size);
  std::vector<render::TextureHandle> handles;
  for (std::uint32_t i = 0; i < columns * rows; ++i) {
    scene::TextureData texture;
    texture.name = "colour " + std::to_string(i);
    texture.width = texture.height = 1;
    const glm::u8vec4 c = textureColor(i);
    texture.rgba = {c.r, c.g, c.b, c.a};
    texture.mipmaps = false;
    render::MaterialImages images;
    images.baseColor = pool_->textures().addImage(texture, render::TexelEncoding::Srgb);
    handles.push_back(pool_->textures().addMaterial(images));
  }
  ASSERT_EQ(pool_->textures().count(), columns * rows + 1) << "the white texels' set, then one per material";
  const float cell = 2.0f / float(columns);
  for (std::uint32_t i = 0; i < columns * rows; ++i) {
    const glm::vec3 centre(-1.0f + cell * (float(i % columns) + 0.5f), -0.8f + cell * (float(i / columns) + 0.5f), 0.0f);
    const ecs::Entity e = addQuad(centre, cell * 0.8f, glm::vec4(1.0f));
    registry_.get<render::MeshRenderable>(e).textures = handles[i];
  }
  const glm::vec3 eye(0.0f, 0.0f, 40.0f);
  const render::CameraView camera =
      render::CameraView::lookAt(eye, {0.0f, 0.0f, 0.0f}, 2.0f * std::atan(1.05f / 40.0f), 1.0f, 1.0f);
  const Frame frame = render(camera);
  const glm::mat4 viewProj = camera.proj * camera.view;
  int wrong = 0;
  double worst = 0.0;
  for (std::uint32_t i = 0; i < columns * rows; ++i) {
    const glm::vec3 centre(-1.0f + cell * (float(i % columns) + 0.5f), -0.8f + cell * (float(i / columns) + 0.5f), 0.0f);
    const glm::vec4 clip = viewProj * glm::vec4(centre, 1.0f);
    const auto x = std::uint32_t((clip.x / clip.w * 0.5f + 0.5f) * float(size));
    const auto y = std::uint32_t((clip.y / clip.w * 0.5f + 0.5f) * float(size));
    const glm::dvec3 expected = gputest::referenceShading(render::RendererDesc{}, gputest::linearColor(textureColor(i)),
                                                          0.5, glm::dvec3(eye), glm::dvec3(centre), {0.0, 0.0, 1.0});
    const double error = glm::length(gputest::linearColor(frame.pixel(x, y)) - expected);
    worst = std::max(worst, error);
    if (error > 0.02) {
      ++wrong;
      ADD_FAILURE() << "square " << i << " at pixel " << x << "," << y << ": colour error " << error;
    }
  }
  std::printf("%u squares, %d wrong (worst colour error %.4f)\n", columns * rows, wrong, worst);
}

}  // namespace
