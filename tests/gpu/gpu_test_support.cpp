#include "gpu_test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/math.h"
#include "engine/render/components.h"
#include "engine/scene/transform.h"
#include "test_device.h"

namespace gputest {

std::size_t differingPixels(const Frame& a, const Frame& b) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < a.depth.size(); ++i) {
    const auto pixel = [i](const Frame& f) { return f.rgba.begin() + std::ptrdiff_t(4 * i); };
    count += a.depth[i] != b.depth[i] || !std::equal(pixel(a), pixel(a) + 4, pixel(b));
  }
  return count;
}

using namespace engine;

std::unique_ptr<gpu::Context> createTestContext(bool synchronizationValidation) {
  gpu::ContextDesc desc;
  desc.applicationName = "hermite_sdf gpu tests";
  const auto device = hsdftest::testDevicePreference();
  if (!device) {
    ADD_FAILURE() << "cannot create the GPU test context: " << device.error().message;
    return nullptr;
  }
  desc.device = *device;
  desc.validation = true;
  desc.synchronizationValidation = synchronizationValidation;
  auto context = gpu::Context::create(desc);
  if (!context) {
    ADD_FAILURE() << "cannot create the GPU test context on " << hsdftest::describeTestDevice() << ": "
                  << context.error().message;
    return nullptr;
  }
  return std::move(context.value());
}

std::vector<NamedTransform> userTransforms(const glm::vec3& pivot) {
  const glm::mat4 toOrigin = glm::translate(glm::mat4(1.0f), -pivot);
  const glm::mat4 back = glm::translate(glm::mat4(1.0f), pivot);
  const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), 0.6f, glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f)));
  const glm::mat4 mirrorX = glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f));
  const glm::mat4 stretch = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 2.5f, 0.4f));
  const glm::mat4 mirrorStretch = glm::scale(glm::mat4(1.0f), glm::vec3(0.5f, -1.6f, 1.0f));
  const glm::mat4 identity(1.0f);
  return {{"mirror x", identity, back * turn * mirrorX * toOrigin},
          {"rotation, scale (1, 2.5, 0.4)", identity, back * turn * stretch * toOrigin},
          {"mirroring non-uniform parent, rotated child (shear)", back * mirrorStretch, turn * toOrigin}};
}

std::vector<CameraSetup> extremeCameras(const glm::vec3& center, float radius) {
  constexpr float kDegree = 3.14159265f / 180.0f;
  auto orbit = [&](glm::uvec2 size, float fovY, float distance) {
    const glm::vec3 eye = math::orbitEye(center, distance * radius, 0.7f, 0.35f);
    return render::CameraView::lookAt(eye, center, fovY, 0.01f * radius, float(size.x) / float(size.y));
  };
  // 300x7 keeps a horizontal field of view of 0.9 rad (a 0.9 rad vertical one would make it ~175
  // degrees wide). A field of view of 10 degrees needs the camera ~11.5 radii away to frame the
  // object; 150 degrees at 1.2 radii (the eye inside the grid's bounds) shows it in the middle,
  // stretched towards the edges.
  const float wideFovY = 2.0f * std::atan(std::tan(0.45f) * 7.0f / 300.0f);
  return {{"1x1", {1, 1}, orbit({1, 1}, 0.9f, 2.0f)},
          {"7x300", {7, 300}, orbit({7, 300}, 0.9f, 2.0f)},
          {"300x7", {300, 7}, orbit({300, 7}, wideFovY, 2.0f)},
          {"fov 10 deg", {128, 128}, orbit({128, 128}, 10.0f * kDegree, 12.0f)},
          {"fov 150 deg", {128, 128}, orbit({128, 128}, 150.0f * kDegree, 1.2f)},
          {"far away", {128, 128}, orbit({128, 128}, 0.9f, 60.0f)}};
}

glm::dvec3 decodeNormal(const std::vector<std::uint8_t>& normalRgba, std::size_t i) {
  const std::uint8_t* c = &normalRgba[i * 4];
  // DEBUG_VIEW_NORMALS writes n * 0.5 + 0.5 into an sRGB target: decode sRGB first.
  auto linear = [](std::uint8_t v) {
    const double s = v / 255.0;
    return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
  };
  return glm::normalize(glm::dvec3(linear(c[0]), linear(c[1]), linear(c[2])) * 2.0 - 1.0);
}

glm::dvec3 linearColor(glm::u8vec4 srgb) {
  auto decode = [](std::uint8_t c) {
    const double s = double(c) / 255.0;
    return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
  };
  return {decode(srgb.r), decode(srgb.g), decode(srgb.b)};
}

glm::dvec3 referenceShading(const render::RendererDesc& desc, const glm::dvec3& baseColor, double roughness,
                            const glm::dvec3& eye, const glm::dvec3& position, const glm::dvec3& normal,
                            double occlusion) {
  const glm::dvec3 v = glm::normalize(eye - position);
  const glm::dvec3 l = glm::normalize(glm::dvec3(desc.lightDirection));
  const glm::dvec3 h = glm::normalize(l + v);
  const double diffuse = std::max(glm::dot(normal, l), 0.0);
  const double shininess = 128.0 + (8.0 - 128.0) * std::clamp(roughness, 0.0, 1.0);
  const double specular = std::pow(std::max(glm::dot(normal, h), 0.0), shininess) * (1.0 - roughness) * 0.5;
  const double ambient = double(desc.ambient) * (0.6 + 0.4 * normal.y) * occlusion;
  const glm::dvec3 light = glm::dvec3(1.0, 0.97, 0.92) * double(desc.lightIntensity);  // Renderer's light colour
  return baseColor * (ambient + diffuse * light) + specular * light;
}

void GpuTest::SetUp() {
  context_ = createTestContext(useSynchronizationValidation());
  ASSERT_NE(context_, nullptr);
  pool_ = std::make_unique<render::MeshPool>(*context_);
  const std::vector<glm::vec3> positions = {{-0.5f, -0.5f, 0.0f}, {0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 0.0f}, {-0.5f, 0.5f, 0.0f}};
  const std::vector<glm::vec3> normals(4, glm::vec3(0.0f, 0.0f, 1.0f));
  const std::vector<std::uint32_t> indices = {0, 1, 2, 0, 2, 3};
  quad_ = pool_->add(positions, normals, indices);
}

void GpuTest::TearDown() {
  if (!context_) return;
  renderer_.reset();
  pool_.reset();
  const auto messages = context_->validationMessages();
  EXPECT_EQ(context_->validationMessageCount(), 0u) << (messages.empty() ? "" : messages.front());
  const std::uint32_t beforeDestruction = context_->validationMessageCount();
  EXPECT_EQ(hsdftest::messagesThroughDestruction(context_), beforeDestruction)
      << "objects left at device destruction (see the log)";
}

void GpuTest::createRenderer(std::uint32_t width, std::uint32_t height) {
  renderer_ = std::make_unique<render::Renderer>(*context_, render::RendererDesc{}, VkExtent2D{width, height});
  // The meshes alone: every fixture starts here and adds the SDF features it tests (their one list:
  // hsdf::addRenderFeatures), so that a test of one feature pays for no other's pipelines.
  const Status added = renderer_->addFeature(std::make_unique<render::MeshFeature>(*pool_));
  ASSERT_TRUE(added.ok()) << added.error().message;
}

Frame GpuTest::render(const render::CameraView& camera, std::uint32_t frames) {
  scene::updateWorldTransforms(registry_);
  for (std::uint32_t i = 1; i < frames; ++i) renderer_->renderFrame(registry_, camera);
  return renderWith(camera, 0);
}

Frame GpuTest::renderWith(const render::CameraView& camera, std::uint32_t debugView) {
  render::FrameSettings settings;
  settings.debugView = debugView;
  return renderWith(camera, settings);
}

Frame GpuTest::renderWith(const render::CameraView& camera, const render::FrameSettings& settings) {
  renderer_->renderFrame(registry_, camera, settings);
  Frame frame;
  frame.width = renderer_->extent().width;
  frame.height = renderer_->extent().height;
  frame.rgba = renderer_->readbackColor();
  frame.depth = renderer_->readbackDepth();
  return frame;
}

ecs::Entity GpuTest::addQuad(const glm::vec3& center, float size, const glm::vec4& color) {
  const ecs::Entity entity = registry_.create();
  scene::Transform transform;
  transform.translation = center;
  transform.scale = glm::vec3(size, size, 1.0f);
  registry_.emplace<scene::Transform>(entity, transform);
  render::MeshRenderable renderable;
  renderable.mesh = quad_;
  renderable.color = color;
  registry_.emplace<render::MeshRenderable>(entity, renderable);
  return entity;
}

}  // namespace gputest
