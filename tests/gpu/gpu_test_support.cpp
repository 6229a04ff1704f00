#include "gpu_test_support.h"

#include "engine/render/components.h"
#include "engine/scene/transform.h"

namespace gputest {

using namespace engine;

std::unique_ptr<gpu::Context> createTestContext(bool synchronizationValidation) {
  gpu::ContextDesc desc;
  desc.applicationName = "hermite_sdf gpu tests";
  desc.device = gpu::DevicePreference::Software;
  desc.validation = true;
  desc.synchronizationValidation = synchronizationValidation;
  auto context = gpu::Context::create(desc);
  if (!context) {
    ADD_FAILURE() << "cannot create the lavapipe test context: " << context.error().message;
    return nullptr;
  }
  return std::move(context.value());
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
  context_.reset();
}

void GpuTest::createRenderer(std::uint32_t width, std::uint32_t height) {
  renderer_ = std::make_unique<render::Renderer>(*context_, render::RendererDesc{}, VkExtent2D{width, height});
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
