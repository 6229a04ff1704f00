// Double-sided meshes (MeshRenderable::doubleSided, glTF material doubleSided): drawn without
// back-face culling in the depth prepass and in the shading pass, a back face lit with its normal
// reversed. Every frame is compared pixel by pixel with a CPU ray cast of the same triangles, both
// sides, and with shared/lighting.glsl written again on the CPU (referenceShading).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "engine/core/files.h"
#include "engine/core/image_io.h"
#include "engine/core/math.h"
#include "engine/render/components.h"
#include "engine/render/scene_instantiate.h"
#include "engine/scene/gltf/gltf_loader.h"
#include "engine/scene/transform.h"
#include "device_tolerances.h"
#include "gpu_test_support.h"
#include "shared/host_device.h"
#include "test_files.h"

namespace gputest {
namespace {

using namespace engine;

constexpr float kZNear = 0.05f;
constexpr double kColourTolerance = 0.04;  // linear; 8-bit sRGB rounding is below 0.01 here

// Flat triangles placed in the world, as the renderer must draw them.
struct Surface {
  std::vector<glm::dvec3> corners;  // three per triangle, world space
  std::vector<glm::dvec3> normals;  // one per triangle: its vertex normal in world space (unit)
  bool doubleSided = false;
  glm::dvec3 color{0.8};
  double roughness = 0.5;
  glm::dvec3 emissive{0.0};  // added to the lit colour (glTF emission)
};

// A mesh primitive (flat: one normal per triangle, from its counter-clockwise winding) placed by
// `model` into a Surface; normals go through the inverse transpose, as mesh.vert does.
Surface place(const scene::MeshPrimitiveData& mesh, const glm::mat4& model, bool doubleSided) {
  Surface surface;
  surface.doubleSided = doubleSided;
  const glm::dmat4 m(model);
  const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(m)));
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    glm::dvec3 p[3];
    for (int k = 0; k < 3; ++k) p[k] = glm::dvec3(mesh.positions[mesh.indices[t + std::size_t(k)]]);
    for (const glm::dvec3& c : p) surface.corners.push_back(glm::dvec3(m * glm::dvec4(c, 1.0)));
    surface.normals.push_back(glm::normalize(normalMatrix * glm::cross(p[1] - p[0], p[2] - p[0])));
  }
  return surface;
}

// lighting.glsl's normalTowardEye, in double: what the shading does with a normal facing away.
glm::dvec3 normalTowardEye(const glm::dvec3& n, const glm::dvec3& v) {
  const double nv = glm::dot(n, v);
  if (nv >= 1e-3) return n;
  const glm::dvec3 across = n - nv * v;
  const double len = glm::length(across);
  if (len < 1e-6) return v;
  return glm::normalize(across / len + 1e-3 * v);
}

struct Hit {
  int triangle = -1;  // -1: nothing drawn at this ray
  double t = 0.0;
  bool backFace = false;
};

// Every triangle `ray` meets, nearest first, each with the side it shows (either side).
std::vector<Hit> castAll(const Surface& surface, const math::Ray& ray) {
  std::vector<Hit> hits;
  for (std::size_t i = 0; i < surface.normals.size(); ++i) {
    const glm::dvec3 a = surface.corners[3 * i], e1 = surface.corners[3 * i + 1] - a, e2 = surface.corners[3 * i + 2] - a;
    const glm::dvec3 p = glm::cross(ray.direction, e2);
    const double det = glm::dot(e1, p);
    if (std::abs(det) < 1e-14) continue;
    const glm::dvec3 s = ray.origin - a, q = glm::cross(s, e1);
    const double u = glm::dot(s, p) / det, v = glm::dot(ray.direction, q) / det, t = glm::dot(e2, q) / det;
    if (u < 0.0 || v < 0.0 || u + v > 1.0 || t <= 0.0) continue;
    hits.push_back({int(i), t, glm::dot(surface.normals[i], ray.direction) > 0.0});
  }
  std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.t < b.t; });
  return hits;
}

// The nearest triangle the renderer should draw along `ray`: both sides of a double-sided surface,
// only the side the normal points to of a single-sided one.
Hit cast(const Surface& surface, const math::Ray& ray) {
  for (const Hit& hit : castAll(surface, ray))
    if (!hit.backFace || surface.doubleSided) return hit;
  return {};
}

struct Comparison {
  int front = 0, back = 0;  // pixels whose expected surface is a front / back face
  int wrongColour = 0, wrongDepth = 0, noObject = 0, drawnOverNothing = 0;
  int backDiscriminating = 0;  // back-face pixels that an unreversed normal would light visibly differently
  double worstColour = 0.0;
};

// Every pixel of `frame` against the CPU cast: coverage (depth 0 where nothing is expected), depth,
// a visibility id wherever depth was written, and the colour shadeSurface gives the side seen with
// its normal facing the eye. Pixels whose corners see other triangles (edges) are not called.
Comparison compare(const Frame& frame, const std::vector<glm::uvec2>& visibility, const Surface& surface,
                   const render::CameraView& camera, const render::RendererDesc& desc, const glm::vec3& eye) {
  Comparison result;
  const glm::ivec2 size(int(frame.width), int(frame.height));
  for (std::uint32_t y = 0; y < frame.height; ++y) {
    for (std::uint32_t x = 0; x < frame.width; ++x) {
      const glm::vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
      const math::Ray ray = math::pixelRay(camera.view, camera.proj, centre, size);
      const Hit hit = cast(surface, ray);
      bool edge = false;
      for (const glm::vec2 offset : {glm::vec2(-0.5f, -0.5f), glm::vec2(0.5f, -0.5f), glm::vec2(-0.5f, 0.5f), glm::vec2(0.5f, 0.5f)})
        edge = edge || cast(surface, math::pixelRay(camera.view, camera.proj, centre + offset, size)).triangle != hit.triangle;
      if (edge) continue;
      const float depth = frame.depthAt(x, y);
      if (hit.triangle < 0) {
        result.drawnOverNothing += depth != 0.0f;
        continue;
      }
      (hit.backFace ? result.back : result.front) += 1;
      const glm::dvec3 position = ray.origin + hit.t * ray.direction;
      const glm::dvec4 clip = glm::dmat4(camera.proj) * glm::dmat4(camera.view) * glm::dvec4(position, 1.0);
      result.wrongDepth += std::abs(double(depth) - clip.z / clip.w) > DeviceTolerances{}.meshDepthAbsolute;
      // The viewer as the shading sees it: the eye point, or a point one unit back along an
      // orthographic camera's parallel ray (the lighting's view vector is then the view axis).
      const glm::dvec3 viewer = camera.orthographic() ? position - ray.direction : glm::dvec3(eye);
      result.noObject += visibility[std::size_t(y) * frame.width + x].x == 0u;
      const glm::dvec3 normal = surface.normals[std::size_t(hit.triangle)];
      const glm::dvec3 seen = hit.backFace ? -normal : normal;  // the glTF rule: a back face's normal reversed
      const glm::dvec3 expected =
          referenceShading(desc, surface.color, surface.roughness, viewer, position, seen) + surface.emissive;
      const double error = glm::length(linearColor(frame.pixel(x, y)) - expected);
      result.worstColour = std::max(result.worstColour, error);
      result.wrongColour += error > kColourTolerance;
      if (hit.backFace) {
        // What the shading would give the unreversed normal (bent toward the eye, mesh.frag's
        // silhouette fix): the case under test must look different from it.
        const glm::dvec3 bent = normalTowardEye(normal, glm::normalize(viewer - position));
        const glm::dvec3 unreversed = referenceShading(desc, surface.color, surface.roughness, viewer, position, bent);
        result.backDiscriminating += glm::length(unreversed - expected) > 4.0 * kColourTolerance;
      }
    }
  }
  std::printf("front %d, back %d (discriminating %d), wrong colour %d (worst %.3f), wrong depth %d, no object %d, "
              "drawn over nothing %d\n",
              result.front, result.back, result.backDiscriminating, result.wrongColour, result.worstColour,
              result.wrongDepth, result.noObject, result.drawnOverNothing);
  return result;
}

void expectMatches(const Comparison& c) {
  EXPECT_EQ(c.wrongColour, 0) << "pixels lit unlike their side (worst colour error " << c.worstColour << ")";
  EXPECT_EQ(c.wrongDepth, 0) << "pixels whose depth is not the nearest surface's";
  EXPECT_EQ(c.noObject, 0) << "pixels with depth but no object in the visibility buffer";
  EXPECT_EQ(c.drawnOverNothing, 0) << "pixels drawn where no surface is to be drawn";
}

// A unit square in z = 0, facing +Z (counter-clockwise from +Z), flat.
scene::MeshPrimitiveData square() {
  scene::MeshPrimitiveData mesh;
  mesh.positions = {{-0.5f, -0.5f, 0.0f}, {0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 0.0f}, {-0.5f, 0.5f, 0.0f}};
  mesh.normals.assign(4, glm::vec3(0.0f, 0.0f, 1.0f));
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return mesh;
}

// A box without a lid (the explorer's zero-thickness cup): five faces of [-0.5, 0.5]^3, wound
// outwards, flat. From above, the inside of the walls and of the floor are back faces.
scene::MeshPrimitiveData openBox() {
  scene::MeshPrimitiveData mesh;
  for (int c = 0; c < 8; ++c) mesh.positions.push_back(glm::vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1) - 0.5f);
  // -Z, +Z, -Y (floor), -X, +X; no +Y.
  mesh.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  mesh.normals.assign(8, glm::vec3(0.0f, 1.0f, 0.0f));  // unused: flat
  mesh.flatNormals = true;
  return mesh;
}

class DoubleSidedTest : public GpuTest {
 protected:
  void createLitRenderer(std::uint32_t size, const glm::vec3& lightDirection) {
    desc_.lightDirection = lightDirection;
    renderer_ = std::make_unique<render::Renderer>(*context_, desc_, VkExtent2D{size, size});
    ASSERT_TRUE(renderer_->addFeature(std::make_unique<render::MeshFeature>(*pool_)).ok());
  }

  // `mesh` as one glTF node with `model` as its matrix and `material`, through the importer's path
  // (instantiateScene): its one renderable.
  const render::MeshRenderable& instantiateNode(const scene::MeshPrimitiveData& mesh, const glm::mat4& model,
                                                const scene::MaterialData& material) {
    scene::SceneData data;
    data.meshes.push_back({"mesh", {mesh}});
    data.meshes[0].primitives[0].material = 0;
    data.materials.push_back(material);
    scene::NodeData node;
    node.mesh = 0;
    node.local = node.world = model;
    data.nodes.push_back(node);
    const render::InstantiatedScene scene = render::instantiateScene(data, registry_, *pool_);
    EXPECT_EQ(scene.renderables.size(), 1u);
    return registry_.get<render::MeshRenderable>(scene.renderables.at(0));
  }

  // `mesh` as one glTF node (instantiateNode) with a material of the given sidedness; returns the
  // Surface the frame must show.
  Surface addNode(const scene::MeshPrimitiveData& mesh, const glm::mat4& model, bool doubleSided, glm::vec4 color,
                  glm::vec3 emissive = glm::vec3(0.0f)) {
    scene::MaterialData material;
    material.baseColor = color;
    material.roughness = 0.4f;
    material.doubleSided = doubleSided;
    material.emissive = emissive;
    EXPECT_EQ(instantiateNode(mesh, model, material).doubleSided, doubleSided) << "the material's flag reaches the draw";
    Surface surface = place(mesh, model, doubleSided);
    surface.color = glm::dvec3(color);
    surface.roughness = material.roughness;
    surface.emissive = glm::dvec3(emissive);
    return surface;
  }

  Comparison renderAndCompare(const Surface& surface, const glm::vec3& eye) {
    return renderAndCompare(surface, render::CameraView::lookAt(eye, {0.0f, 0.0f, 0.0f}, 0.8f, kZNear, 1.0f));
  }
  Comparison renderAndCompare(const Surface& surface, const render::CameraView& camera) {
    const Frame frame = render(camera);
    return compare(frame, renderer_->readbackVisibility(), surface, camera, desc_, camera.position);
  }

  render::RendererDesc desc_;
};

// Why: the case glTF's doubleSided exists for (a leaf card, a sheet of paper): seen from behind, a
// double-sided square must be drawn, and lit as its back face, whose normal is the reverse of the
// one the file gives. Tricky because the shading already turned a normal that faces away toward
// the eye for the silhouette fix (normalTowardEye): without the reversal the back face is still
// drawn, but lit as a surface seen edge-on; the view is oblique and the light behind the square so
// that the two differ on most pixels (backDiscriminating).
TEST_F(DoubleSidedTest, ADoubleSidedSquareSeenFromBehindIsLitAsItsBackFace) {
  const std::uint32_t size = 96;
  createLitRenderer(size, {-0.3f, 0.5f, -1.0f});  // the light on the back side
  const Surface surface = addNode(square(), glm::scale(glm::mat4(1.0f), glm::vec3(1.6f)), true, {0.9f, 0.6f, 0.2f, 1.0f});
  const Comparison c = renderAndCompare(surface, {1.4f, 0.6f, -2.2f});
  EXPECT_EQ(c.front, 0);
  EXPECT_GT(c.back, 1500) << "the square seen from behind is drawn";
  EXPECT_GT(c.backDiscriminating, c.back / 2) << "the view must tell a reversed normal from an unreversed one";
  expectMatches(c);
}

// Why: a single-sided surface (the glTF default) keeps back-face culling: the same square seen
// from behind draws nothing, and seen from the front it is drawn as before.
TEST_F(DoubleSidedTest, ASingleSidedSquareSeenFromBehindIsNotDrawn) {
  const std::uint32_t size = 64;
  createLitRenderer(size, {-0.3f, 0.5f, -1.0f});
  const Surface surface = addNode(square(), glm::scale(glm::mat4(1.0f), glm::vec3(1.6f)), false, {0.9f, 0.6f, 0.2f, 1.0f});
  const Comparison behind = renderAndCompare(surface, {1.4f, 0.6f, -2.2f});
  EXPECT_EQ(behind.front + behind.back, 0);
  EXPECT_EQ(behind.drawnOverNothing, 0) << "the back of a single-sided square was drawn";
  const Comparison front = renderAndCompare(surface, {1.4f, 0.6f, 2.2f});
  EXPECT_GT(front.front, 600);
  expectMatches(front);
}

// Why: the depth prepass writes depth and the shading pass draws where its depth is EQUAL; both
// must draw a primitive with the same cull mode. A prepass without culling under a shading pass
// with culling leaves holes (depth of the inside, no colour: the background, the explorer's cup);
// the other way round the inside is shaded wherever its depth happens to equal the outside's
// (nowhere) or the outside's depth hides it. Tricky because a box without a lid, seen from above,
// shows front faces (the outside of the near walls) and back faces (the inside of the far walls
// and of the floor) in one draw, next to each other and in front of each other; every pixel's
// depth, visibility id and colour must be the nearest side's.
TEST_F(DoubleSidedTest, PrepassAndShadingAgreeOnAnOpenBoxSeenFromAbove) {
  const std::uint32_t size = 128;
  createLitRenderer(size, {0.4f, 1.0f, 0.3f});
  const glm::mat4 model = glm::rotate(glm::mat4(1.0f), 0.5f, glm::vec3(0.0f, 1.0f, 0.0f));
  const Surface surface = addNode(openBox(), model, true, {0.3f, 0.7f, 0.9f, 1.0f});
  const Comparison c = renderAndCompare(surface, {0.9f, 2.4f, 1.3f});
  EXPECT_GT(c.front, 1000) << "the outside of the near walls";
  EXPECT_GT(c.back, 2000) << "the inside: far walls and floor";
  EXPECT_GT(c.backDiscriminating, 500) << "the inside lit unlike an unreversed normal";
  expectMatches(c);
}

// Why: a mirroring node (negative determinant: a glTF scale of -1) reverses the triangles' winding
// on screen; the mesh feature draws mirrored objects with clockwise front faces. Culling is off for
// a double-sided one, so a wrong front face no longer hides anything: it only swaps which side
// gl_FrontFacing calls the front, and every pixel is lit as the other side. Tricky because only
// the lighting shows it; the box is mirrored and rotated (sheared by nothing, winding reversed),
// seen from above, inside and outside in one frame.
TEST_F(DoubleSidedTest, AMirroredDoubleSidedBoxIsLitAsTheSideSeen) {
  const std::uint32_t size = 128;
  createLitRenderer(size, {0.4f, 1.0f, 0.3f});
  const glm::mat4 model = glm::scale(glm::rotate(glm::mat4(1.0f), 0.5f, glm::vec3(0.0f, 1.0f, 0.0f)), glm::vec3(-1.0f, 1.0f, 1.0f));
  ASSERT_LT(glm::determinant(model), 0.0f);
  const Surface surface = addNode(openBox(), model, true, {0.3f, 0.7f, 0.9f, 1.0f});
  const Comparison c = renderAndCompare(surface, {0.9f, 2.4f, 1.3f});
  EXPECT_GT(c.front, 1000);
  EXPECT_GT(c.back, 2000);
  EXPECT_GT(c.backDiscriminating, 500) << "the inside lit unlike an unreversed normal";
  expectMatches(c);
}

// Why: an orthographic camera (a glTF "orthographic" camera node) must draw the mesh through its
// parallel projection: the open box's walls keep their size at any depth, depth is linear between
// znear and zfar (compared with the projection of each ray's hit), and the lighting's view vector
// is the view axis at every pixel, not the direction to the camera's point (the specular highlight
// moves otherwise). Tricky because the box is seen from above at a slant, inside and outside in one
// frame, through a camera made as the importer makes it (CameraView::fromWorld of a Camera).
TEST_F(DoubleSidedTest, AnOpenBoxSeenThroughAnOrthographicCamera) {
  const std::uint32_t size = 128;
  createLitRenderer(size, {0.4f, 1.0f, 0.3f});
  const glm::mat4 model = glm::rotate(glm::mat4(1.0f), 0.5f, glm::vec3(0.0f, 1.0f, 0.0f));
  const Surface surface = addNode(openBox(), model, true, {0.3f, 0.7f, 0.9f, 1.0f});
  render::Camera ortho;
  ortho.projection = render::Projection::kOrthographic;
  ortho.xmag = ortho.ymag = 0.9f;
  ortho.znear = 0.5f;
  ortho.zfar = 6.0f;
  const glm::mat4 pose = glm::inverse(math::lookAt({0.9f, 2.4f, 1.3f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}));
  const Expected<render::CameraView> camera = render::CameraView::fromWorld(pose, ortho, 1.0f);
  ASSERT_TRUE(camera.ok()) << camera.error().message;
  const Comparison c = renderAndCompare(surface, *camera);
  EXPECT_GT(c.front, 1000) << "the outside of the near walls";
  EXPECT_GT(c.back, 2000) << "the inside: far walls and floor";
  expectMatches(c);
}

// Why: single- and double-sided objects in one frame are drawn by different pipelines, in batches
// sorted by sidedness and mirroring: each object must be drawn by its own batch (a single-sided
// closed box beside a double-sided open one, both mirrored and not). Tricky because a batch's
// range off by one draws an object with the other's cull mode or front face, which shows only on
// some of its pixels.
TEST_F(DoubleSidedTest, SingleAndDoubleSidedMirroredAndNotInOneFrame) {
  const std::uint32_t size = 160;
  createLitRenderer(size, {0.4f, 1.0f, 0.3f});
  scene::MeshPrimitiveData closed = openBox();
  closed.indices.insert(closed.indices.end(), {2, 6, 3, 3, 6, 7});  // the lid: +Y
  Surface all;
  auto add = [&](const scene::MeshPrimitiveData& mesh, glm::vec3 at, float mirror, bool doubleSided) {
    const glm::mat4 model = glm::scale(glm::translate(glm::mat4(1.0f), at), glm::vec3(mirror, 1.0f, 1.0f) * 0.8f);
    const Surface s = addNode(mesh, model, doubleSided, {0.3f, 0.7f, 0.9f, 1.0f});
    all.corners.insert(all.corners.end(), s.corners.begin(), s.corners.end());
    all.normals.insert(all.normals.end(), s.normals.begin(), s.normals.end());
    all.color = s.color;
    all.roughness = s.roughness;
  };
  add(openBox(), {-0.6f, 0.0f, -0.6f}, 1.0f, true);
  add(closed, {0.6f, 0.0f, -0.6f}, -1.0f, false);
  add(openBox(), {-0.6f, 0.0f, 0.6f}, -1.0f, true);
  add(closed, {0.6f, 0.0f, 0.6f}, 1.0f, false);
  // Both boxes' kinds are in `all`; the closed ones show no back face from outside, so casting
  // every triangle two-sided finds the same surfaces.
  all.doubleSided = true;
  const Comparison c = renderAndCompare(all, {1.2f, 3.4f, 2.0f});
  EXPECT_GT(c.front, 2000);
  EXPECT_GT(c.back, 1000);
  expectMatches(c);
}

// glTF materials beyond the factors (emission), drawn by the same mesh pipelines.
class MeshMaterialTest : public DoubleSidedTest {};

// Why: an emissive sign or lamp (glTF emissiveFactor) shows its own colour whatever the light
// does. Tricky because the lighting gives a face turned from the light almost nothing (a black base
// colour: no ambient, no diffuse), so the emission must be added after it, not multiplied into the
// base colour; the frame is compared with the CPU reference plus the emission on every pixel.
TEST_F(MeshMaterialTest, AnEmissiveFaceTurnedFromTheLightShowsItsEmission) {
  const std::uint32_t size = 64;
  createLitRenderer(size, {0.2f, 0.3f, -1.0f});  // the light behind the square
  const glm::vec3 emission(0.9f, 0.45f, 0.1f);
  const Surface surface =
      addNode(square(), glm::scale(glm::mat4(1.0f), glm::vec3(1.6f)), false, {0.0f, 0.0f, 0.0f, 1.0f}, emission);
  const Comparison c = renderAndCompare(surface, {0.4f, 0.3f, 2.2f});
  EXPECT_GT(c.front, 600);
  expectMatches(c);
}

// The 4 x 4 texels of the checker: a colour of its own each, so that a texel read from the wrong
// row or column shows; opaque, or with `holes` every other texel's alpha 0.6 (153).
glm::u8vec4 checkerTexel(int column, int row, bool holes = false) {
  const bool odd = (column + row) % 2 != 0;
  return {std::uint8_t(40 + 60 * column), std::uint8_t(230 - 60 * row), std::uint8_t(odd ? 220 : 30),
          std::uint8_t(holes && odd ? 153 : 255)};
}

// A glTF file written into `folder`: the unit square in z = 0 facing +Z with TEXCOORD_0 (glTF's v
// runs down the image: the square's top edge is the image's first row), its material's
// baseColorFactor `factor` and a baseColorTexture, checker.png (4 x 4, NEAREST, clamped), beside it;
// `material` adds fields to the material (e.g. its alphaMode), `pbr` to its pbrMetallicRoughness
// (each ending in a comma), and `holes` gives the checker's odd texels alpha 0.6. `second`, when
// given, is a second 4 x 4 RGBA image, second.png, glTF texture 1 (the same sampler). `tangent`,
// when given, is every vertex's TANGENT.
std::filesystem::path writeCheckerQuad(const std::filesystem::path& folder, const glm::vec4& factor,
                                       const std::string& material = "", bool holes = false, const std::string& pbr = "",
                                       const std::vector<std::uint8_t>& second = {},
                                       const std::optional<glm::vec4>& tangent = std::nullopt) {
  std::filesystem::create_directories(folder);
  if (!second.empty()) {
    EXPECT_TRUE(writePng(folder / "second.png", second, 4, 4, 4).ok());
  }
  const std::string textures = second.empty() ? R"([{"source": 0, "sampler": 0}])"
                                              : R"([{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}])";
  const std::string images = second.empty() ? R"([{"uri": "checker.png"}])" : R"([{"uri": "checker.png"}, {"uri": "second.png"}])";
  std::vector<std::uint8_t> texels;
  for (int row = 0; row < 4; ++row)
    for (int column = 0; column < 4; ++column) {
      const glm::u8vec4 t = checkerTexel(column, row, holes);
      texels.insert(texels.end(), {t.r, t.g, t.b, t.a});
    }
  EXPECT_TRUE(writePng(folder / "checker.png", texels, 4, 4, 4).ok());
  const std::vector<float> positions = {-0.5f, -0.5f, 0, 0.5f, -0.5f, 0, 0.5f, 0.5f, 0, -0.5f, 0.5f, 0};
  const std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const std::vector<float> texcoords = {0, 1, 1, 1, 1, 0, 0, 0};
  const std::vector<std::uint32_t> indices = {0, 1, 2, 0, 2, 3};
  std::vector<std::uint8_t> bin;
  auto append = [&bin](const auto& values) {
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(values.data());
    bin.insert(bin.end(), bytes, bytes + values.size() * sizeof(values[0]));
  };
  append(positions);
  append(normals);
  append(texcoords);
  append(indices);
  if (tangent)
    for (int v = 0; v < 4; ++v) append(std::vector<float>{tangent->x, tangent->y, tangent->z, tangent->w});
  EXPECT_TRUE(writeBinaryFile(folder / "quad.bin", bin).ok());
  const std::string tangentAttribute = tangent ? R"(, "TANGENT": 4)" : "";
  const std::string tangentView = tangent ? R"(, {"buffer": 0, "byteOffset": 152, "byteLength": 64})" : "";
  const std::string tangentAccessor = tangent ? R"(, {"bufferView": 4, "componentType": 5126, "count": 4, "type": "VEC4"})" : "";
  const std::string gltf = R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2)" + tangentAttribute +
                           R"(}, "indices": 3, "material": 0}]}],
    "materials": [{)" + material + R"("pbrMetallicRoughness": {"baseColorFactor": [)" +
                           std::to_string(factor.r) + "," + std::to_string(factor.g) + "," + std::to_string(factor.b) +
                           "," + std::to_string(factor.a) + R"(], "roughnessFactor": 0.6, )" + pbr + R"(
      "baseColorTexture": {"index": 0}}}],
    "textures": )" + textures + R"(,
    "samplers": [{"magFilter": 9728, "minFilter": 9728, "wrapS": 33071, "wrapT": 33071}],
    "images": )" + images + R"(,
    "buffers": [{"uri": "quad.bin", "byteLength": )" + std::to_string(bin.size()) + R"(}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 96, "byteLength": 32}, {"buffer": 0, "byteOffset": 128, "byteLength": 24})" +
                           tangentView + R"(],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 0]},
                  {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                  {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                  {"bufferView": 3, "componentType": 5125, "count": 6, "type": "SCALAR"})" + tangentAccessor + R"(]})";
  EXPECT_TRUE(writeBinaryFile(folder / "quad.gltf", std::vector<std::uint8_t>(gltf.begin(), gltf.end())).ok());
  return folder / "quad.gltf";
}

// Where the ray through `pixel` of a `size` x `size` frame meets the plane at height `z`.
glm::dvec3 pixelRayAtZ(const render::CameraView& camera, std::uint32_t size, glm::vec2 pixel, double z) {
  const math::Ray ray = math::pixelRay(camera.view, camera.proj, pixel, glm::ivec2(int(size)));
  return ray.origin + ((z - ray.origin.z) / ray.direction.z) * ray.direction;
}

// Calls `visit(x, y, texel, centre)` for each pixel whose centre and four corners all see one texel
// of the checker quad (writeCheckerQuad: the unit square in z = 0, 4 x 4 texels, v down the image):
// pixels off the quad or across a texel boundary are skipped, as NEAREST may go either way there.
// `mirrored`: the quad placed with x scaled by -1 (u runs along -x).
template <class Visit>
void forEachCheckerPixel(const render::CameraView& camera, std::uint32_t size, Visit visit, bool mirrored = false) {
  auto texelAt = [&](glm::vec2 pixel) {  // (-1, -1) off the square
    const glm::dvec3 p = pixelRayAtZ(camera, size, pixel, 0.0);
    const double u = (mirrored ? -p.x : p.x) + 0.5, v = 0.5 - p.y;
    if (u < 0.0 || u >= 1.0 || v < 0.0 || v >= 1.0) return glm::ivec2(-1);
    return glm::ivec2(int(u * 4.0), int(v * 4.0));
  };
  for (std::uint32_t y = 0; y < size; ++y) {
    for (std::uint32_t x = 0; x < size; ++x) {
      const glm::vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
      const glm::ivec2 texel = texelAt(centre);
      bool edge = texel.x < 0;
      for (const glm::vec2 offset : {glm::vec2(-0.5f, -0.5f), glm::vec2(0.5f, -0.5f), glm::vec2(-0.5f, 0.5f), glm::vec2(0.5f, 0.5f)})
        edge = edge || texelAt(centre + offset) != texel;
      if (!edge) visit(x, y, texel, centre);
    }
  }
}

// Why: a textured mesh (most glTF scenes) is drawn in its texture times its factor. The file is
// loaded as a user's would be (PNG beside the .gltf, through the importer and instantiateScene),
// and every pixel is compared with the texel its ray hits on the square -- u across, v down the
// image, NEAREST -- times the factor, lit by the CPU reference. Tricky because the v axis runs
// down the image in glTF (a flip shows as rows swapped), the texture is sRGB (read as linear: a
// UNORM upload would brighten every texel) and the factor multiplies the texel, not replaces it.
TEST_F(MeshMaterialTest, ABaseColorTextureIsDrawnTexelByTexelTimesTheFactor) {
  const std::uint32_t size = 96;
  createLitRenderer(size, {0.3f, 0.5f, 1.0f});
  const hsdftest::ScopedTempPath folder("textured_quad");
  const glm::vec4 factor(1.0f, 0.8f, 0.6f, 1.0f);
  const auto data = scene::loadGltf(writeCheckerQuad(folder.path(), factor));
  ASSERT_TRUE(data.ok()) << data.error().message;
  ASSERT_EQ(data->textures.size(), 1u);
  const render::InstantiatedScene scene = render::instantiateScene(*data, registry_, *pool_);
  ASSERT_EQ(scene.renderables.size(), 1u);
  const glm::vec3 eye(0.0f, 0.0f, 1.6f);
  const render::CameraView camera = render::CameraView::lookAt(eye, {0.0f, 0.0f, 0.0f}, 0.8f, kZNear, 1.0f);
  const Frame frame = render(camera);
  int compared = 0, wrong = 0;
  double worst = 0.0;
  std::array<int, 16> seen{};
  forEachCheckerPixel(camera, size, [&](std::uint32_t x, std::uint32_t y, glm::ivec2 texel, glm::vec2 centre) {
    const glm::dvec3 position = pixelRayAtZ(camera, size, centre, 0.0);
    const glm::dvec3 base = linearColor(checkerTexel(texel.x, texel.y)) * glm::dvec3(factor);
    const glm::dvec3 expected = referenceShading(desc_, base, 0.6, glm::dvec3(eye), position, {0.0, 0.0, 1.0});
    const double error = glm::length(linearColor(frame.pixel(x, y)) - expected);
    worst = std::max(worst, error);
    wrong += error > kColourTolerance;
    ++compared;
    ++seen[std::size_t(texel.y * 4 + texel.x)];
  });
  std::printf("compared %d pixels, wrong %d (worst %.3f)\n", compared, wrong, worst);
  EXPECT_GT(compared, 2000);
  for (int t = 0; t < 16; ++t) EXPECT_GT(seen[std::size_t(t)], 50) << "texel " << t << " is compared on its pixels";
  EXPECT_EQ(wrong, 0) << "pixels unlike their texel times the factor (worst colour error " << worst << ")";
}

// Why: a leaf card, a fence or a grille (glTF alphaMode MASK) is cut out where its alpha is below
// the cutoff, and what lies behind shows there. The checker quad (MASK, cutoff 0.3, factor alpha
// 0.4) has opaque even texels (alpha 0.4 x 1) and odd ones of alpha 0.4 x 0.6 = 0.24, cut out; a
// red square 0.4 behind it must show through the odd texels, lit by the CPU reference, and the
// even ones keep their texel times the factor. Tricky because the alpha is the factor's times the
// texture's (either alone keeps every texel: 0.4 and 0.6 are above the cutoff), because a cut-out
// fragment must leave no depth (the square behind would be culled by the prepass depth test
// otherwise, or shaded with the quad's visibility), and because the shading pass must not draw the
// quad where its prepass fragment was cut out.
TEST_F(MeshMaterialTest, AMaskedQuadShowsWhatLiesBehindItsCutOutTexels) {
  const std::uint32_t size = 96;
  createLitRenderer(size, {0.3f, 0.5f, 1.0f});
  const hsdftest::ScopedTempPath folder("masked_quad");
  const glm::vec4 factor(1.0f, 0.8f, 0.6f, 0.4f);
  const auto data = scene::loadGltf(
      writeCheckerQuad(folder.path(), factor, R"("alphaMode": "MASK", "alphaCutoff": 0.3, )", true));
  ASSERT_TRUE(data.ok()) << data.error().message;
  const render::InstantiatedScene scene = render::instantiateScene(*data, registry_, *pool_);
  ASSERT_EQ(scene.renderables.size(), 1u);
  const glm::dvec3 backColor(0.55, 0.1, 0.08);  // lit, below 1: the frame's UNORM clamps nothing
  const double backZ = -0.4;
  addNode(square(), glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, float(backZ))) *
                        glm::scale(glm::mat4(1.0f), glm::vec3(3.0f)),
          false, glm::vec4(glm::vec3(backColor), 1.0f));
  const glm::vec3 eye(0.0f, 0.0f, 1.6f);
  const render::CameraView camera = render::CameraView::lookAt(eye, {0.0f, 0.0f, 0.0f}, 0.8f, kZNear, 1.0f);
  const Frame frame = render(camera);
  int kept = 0, cut = 0, wrong = 0;
  double worst = 0.0;
  forEachCheckerPixel(camera, size, [&](std::uint32_t x, std::uint32_t y, glm::ivec2 texel, glm::vec2 centre) {
    const bool hole = (texel.x + texel.y) % 2 != 0;
    const glm::dvec3 base = hole ? backColor : linearColor(checkerTexel(texel.x, texel.y, true)) * glm::dvec3(factor);
    const double roughness = hole ? 0.4 : 0.6;
    const glm::dvec3 position = pixelRayAtZ(camera, size, centre, hole ? backZ : 0.0);
    const glm::dvec3 expected = referenceShading(desc_, base, roughness, glm::dvec3(eye), position, {0.0, 0.0, 1.0});
    const double error = glm::length(linearColor(frame.pixel(x, y)) - expected);
    worst = std::max(worst, error);
    wrong += error > kColourTolerance;
    ++(hole ? cut : kept);
  });
  std::printf("kept %d pixels, cut out %d, wrong %d (worst %.3f)\n", kept, cut, wrong, worst);
  EXPECT_GT(kept, 1000);
  EXPECT_GT(cut, 1000);
  EXPECT_EQ(wrong, 0) << "pixels unlike the texel kept or the square behind a cut-out one (worst colour error " << worst
                      << ")";
}

// glTF's material textures beside the base colour: the checker quad's one texture serves as each,
// so a texel's channels are known at every pixel compared.
class MaterialTexturesTest : public MeshMaterialTest {
 protected:
  // The shading inputs of one pixel of the checker quad: its texel, its point, the base colour.
  struct CheckerPixel {
    glm::u8vec4 texel;
    glm::dvec3 position;
    glm::dvec3 base;  // the texel (sRGB) times the factor
    glm::ivec2 at;    // which texel: column, row
  };
  static constexpr glm::vec4 kFactor{1.0f, 0.8f, 0.6f, 1.0f};
  static constexpr glm::vec3 kEye{0.0f, 0.0f, 1.6f};

  // The checker quad with `material` and `pbr` fields (writeCheckerQuad), lit from `light` (desc_'s
  // intensity and ambient, which keep the colours below 1: the frame clamps): every pixel within
  // kColourTolerance of expected(pixel).first, and at least 500 pixels where that is over twice
  // the tolerance from expected(pixel).second, the colour without the texture under test (so that
  // the comparison tells the two apart).
  template <class Expected>
  void expectCheckerQuad(const std::string& material, const std::string& pbr, const glm::vec3& light, Expected expected,
                         const std::vector<std::uint8_t>& second = {}) {
    const std::uint32_t size = 96;
    createLitRenderer(size, light);
    const hsdftest::ScopedTempPath folder("material_textures_quad");
    auto data = scene::loadGltf(writeCheckerQuad(folder.path(), kFactor, material, false, pbr, second, tangent_));
    ASSERT_TRUE(data.ok()) << data.error().message;
    if (derivativeFrame_)
      for (auto& mesh : data->meshes)
        for (auto& primitive : mesh.primitives) primitive.tangents.clear();
    for (const auto& w : data->warnings) ADD_FAILURE() << "unexpected warning: " << w;
    ASSERT_EQ(data->textures.size(), second.empty() ? 1u : 2u);
    const render::InstantiatedScene scene = render::instantiateScene(*data, registry_, *pool_);
    ASSERT_EQ(scene.renderables.size(), 1u);
    if (mirrored_) registry_.get<scene::Transform>(scene.nodes.at(0)).scale = {-1.0f, 1.0f, 1.0f};
    const render::CameraView camera = render::CameraView::lookAt(eye_, {0.0f, 0.0f, 0.0f}, 0.8f, kZNear, 1.0f);
    const Frame frame = render(camera);
    int compared = 0, wrong = 0, discriminating = 0;
    double worst = 0.0;
    forEachCheckerPixel(camera, size, [&](std::uint32_t x, std::uint32_t y, glm::ivec2 texel, glm::vec2 centre) {
      const glm::u8vec4 t = checkerTexel(texel.x, texel.y);
      const CheckerPixel pixel{t, pixelRayAtZ(camera, size, centre, 0.0), linearColor(t) * glm::dvec3(kFactor), texel};
      const auto [with, without] = expected(pixel);
      const double error = glm::length(linearColor(frame.pixel(x, y)) - with);
      worst = std::max(worst, error);
      wrong += error > kColourTolerance;
      discriminating += glm::length(with - without) > 2.0 * kColourTolerance;
      ++compared;
    }, mirrored_);
    std::printf("compared %d pixels, %d discriminating, wrong %d (worst %.3f)\n", compared, discriminating, wrong, worst);
    EXPECT_GT(compared, 2000);
    EXPECT_GT(discriminating, 500) << "pixels where the texture changes the colour";
    EXPECT_EQ(wrong, 0) << "pixels unlike the CPU reference (worst colour error " << worst << ")";
  }

  // The quad with the 4 x 4 normal map at scale 0.8, its tangent along `tangentX` x (+1, or -1 for
  // a mirrored instance), the bitangent +y: each pixel against the CPU reference's tilted normal.
  void expectNormalMappedQuad(double tangentX);  // after normalMap and tiltedNormal, below

  // shadeSurface's colour of the quad at `pixel` with `roughness`, `occlusion` and `normal` (unit).
  glm::dvec3 lit(const CheckerPixel& pixel, double roughness, double occlusion = 1.0,
                 const glm::dvec3& normal = {0.0, 0.0, 1.0}) const {
    return referenceShading(desc_, pixel.base, roughness, glm::dvec3(eye_), pixel.position, normal, occlusion);
  }

  glm::vec3 eye_ = kEye;
  bool mirrored_ = false;  // the quad's node scaled by (-1, 1, 1)
  std::optional<glm::vec4> tangent_;  // every vertex's TANGENT, when given
  // No tangents drawn (those generated at load dropped): the frame from the screen derivatives.
  bool derivativeFrame_ = false;
};

// Why: glTF's roughness is the roughnessFactor times the metallicRoughnessTexture's green, read as
// linear data: a rough and a polished part of one mesh differ in their highlight. Lit from just
// above the eye, the highlight lies on the quad; each pixel must be the CPU reference with
// roughness 0.6 x green / 255. Tricky because the same image is also the base colour, which reads
// it as sRGB: read so for the roughness too, the greens of rows 1-3 shrink (110 -> 0.16, not 0.43).
TEST_F(MaterialTexturesTest, TheMetallicRoughnessTexturesGreenScalesTheRoughness) {
  desc_.lightIntensity = 0.6f;
  expectCheckerQuad("", R"("metallicRoughnessTexture": {"index": 0},)", {0.05f, 0.05f, 1.0f}, [&](const CheckerPixel& p) {
    return std::pair(lit(p, 0.6 * p.texel.g / 255.0), lit(p, 0.6));
  });
}

// Why: glTF's occlusionTexture darkens the ambient light only (1 + strength x (red - 1) of it
// reaches the surface), never the light's direct part. Lit from the front with a strong ambient
// (1.0; the light 0.3), each pixel must be the CPU reference with that part of its ambient term.
// Tricky because occluding the whole colour, or ignoring the strength (0.7), each look plausible.
TEST_F(MaterialTexturesTest, TheOcclusionTexturesRedDarkensTheAmbientLightByItsStrength) {
  desc_.ambient = 1.0f;
  desc_.lightIntensity = 0.3f;
  expectCheckerQuad(R"("occlusionTexture": {"index": 0, "strength": 0.7},)", "", {0.3f, 0.5f, 1.0f}, [&](const CheckerPixel& p) {
    return std::pair(lit(p, 0.6, 1.0 + 0.7 * (p.texel.r / 255.0 - 1.0)), lit(p, 0.6));
  });
}

// Why: glTF's emission is the emissiveFactor times the emissiveTexture (sRGB): a lamp's panel, a
// screen, glowing on a face the light does not reach. Lit from behind the quad, each pixel must be
// its ambient-lit texel plus the texel's linear colour times the factor. Tricky because the
// texture multiplies the factor (not replaces it) and is sRGB (read as UNORM every texel glows
// brighter).
TEST_F(MaterialTexturesTest, TheEmissiveTextureMultipliesTheEmissiveFactorOnAFaceTurnedFromTheLight) {
  const glm::dvec3 factor(0.5, 0.7, 0.9);
  expectCheckerQuad(R"("emissiveTexture": {"index": 0}, "emissiveFactor": [0.5, 0.7, 0.9],)", "", {0.3f, 0.5f, -1.0f},
                    [&](const CheckerPixel& p) {
                      return std::pair(lit(p, 0.6) + factor * linearColor(p.texel), lit(p, 0.6) + factor);
                    });
}

// The normal map of the normal texture test: texel (column, row) tilts the normal by 0.3 x (column
// - 1.5) toward +u and 0.3 x (row - 1.5) toward the image's top (glTF: +x right, +y up).
glm::u8vec4 normalTexel(int column, int row) {
  const double x = 0.3 * (column - 1.5), y = 0.3 * (row - 1.5), z = std::sqrt(1.0 - x * x - y * y);
  const auto encode = [](double c) { return std::uint8_t(std::lround((c * 0.5 + 0.5) * 255.0)); };
  return {encode(x), encode(y), encode(z), 255};
}

// The normal map of normalTexel, as RGBA rows.
std::vector<std::uint8_t> normalMap() {
  std::vector<std::uint8_t> normals;
  for (int row = 0; row < 4; ++row)
    for (int column = 0; column < 4; ++column) {
      const glm::u8vec4 t = normalTexel(column, row);
      normals.insert(normals.end(), {t.r, t.g, t.b, t.a});
    }
  return normals;
}

// The normal texel's tilted normal with scale 0.8 in the frame (tangent, bitangent, normal).
glm::dvec3 tiltedNormal(glm::ivec2 at, const glm::dvec3& tangent, const glm::dvec3& bitangent, const glm::dvec3& normal) {
  const glm::u8vec4 t = normalTexel(at.x, at.y);
  const auto decode = [](std::uint8_t c) { return 2.0 * c / 255.0 - 1.0; };
  return glm::normalize(0.8 * decode(t.r) * tangent + 0.8 * decode(t.g) * bitangent + decode(t.b) * normal);
}

void MaterialTexturesTest::expectNormalMappedQuad(double tangentX) {
  expectCheckerQuad(
      R"("normalTexture": {"index": 1, "scale": 0.8},)", "", {0.3f, 0.5f, 1.0f},
      [&](const CheckerPixel& p) {
        return std::pair(lit(p, 0.6, 1.0, tiltedNormal(p.at, {tangentX, 0, 0}, {0, 1, 0}, {0, 0, 1})), lit(p, 0.6));
      },
      normalMap());
}

// Why: a normal-mapped wall (glTF normalTexture: most real assets) shows its relief in the light; drawn
// with the vertex normals it is flat. The checker quad with a second texture, a 4 x 4 normal map of
// a tilt of its own per texel, scale 0.8: each pixel must be the CPU reference lit with the normal
// the 8-bit texel gives in the quad's frame (u along +x, v down the image: the texel's +y is +y in
// the world), (2 t - 1) with x and y times the scale. Tricky because the bitangent is -dP/dv (glTF's
// v runs down, its green up: a sign slip mirrors every tilt in y), the texel is linear data, and
// the scale applies to x and y only.
TEST_F(MaterialTexturesTest, TheNormalTextureTiltsTheShadingNormalInTheTangentFrame) {
  expectNormalMappedQuad(1.0);
}

// Why: glTF mirrors an instance by a negative scale, and exporters mirror half a model's texture
// coordinates; the tangent must follow the texture's u, now along -x, or every tilt in x turns
// the wrong way. The normal texture test's quad placed with x scaled by -1 (its winding reversed,
// drawn as a front face by the mirrored pipeline state): each pixel against the CPU reference
// with the tangent -x.
TEST_F(MaterialTexturesTest, TheNormalTextureFollowsAMirroredInstancesTextureDirections) {
  mirrored_ = true;
  expectNormalMappedQuad(-1.0);
}

// Why: a primitive without TANGENT gets tangents made at load (engine/scene/tangents.h); where they
// cannot be made (texcoords of zero area, flat normals) the shader builds the frame from the
// screen derivatives of the position and texcoords. That fallback alone, the quad plain and
// mirrored, against the same CPU references as the tests above.
TEST_F(MaterialTexturesTest, WithoutTangentsTheNormalTextureIsReadInTheDerivativeFrame) {
  derivativeFrame_ = true;
  expectNormalMappedQuad(1.0);
}

TEST_F(MaterialTexturesTest, WithoutTangentsAMirroredInstanceIsReadInTheDerivativeFrame) {
  derivativeFrame_ = true;
  mirrored_ = true;
  expectNormalMappedQuad(-1.0);
}

// Why: glTF reverses a double-sided mesh's back-face normal "before the lighting equation is
// evaluated": the tilted normal too, whole. The quad, double-sided, seen and lit from below: each
// pixel against the CPU reference with the front face's tilted normal reversed. Tricky because
// tilting the reversed vertex normal in a frame built from it keeps the tangent's part unreversed.
TEST_F(MaterialTexturesTest, TheNormalTextureOnADoubleSidedBackFaceIsReversedWhole) {
  eye_ = {0.0f, 0.0f, -1.6f};
  expectCheckerQuad(
      R"("doubleSided": true, "normalTexture": {"index": 1, "scale": 0.8},)", "", {0.3f, 0.5f, -1.0f},
      [&](const CheckerPixel& p) {
        return std::pair(lit(p, 0.6, 1.0, -tiltedNormal(p.at, {1, 0, 0}, {0, 1, 0}, {0, 0, 1})), lit(p, 0.6, 1.0, {0, 0, -1}));
      },
      normalMap());
}

// Why: a baked normal map (most real assets) was made in the mesh's TANGENT frame, which glTF asks
// clients to use when the file has one; where it differs from the texture's directions on the
// triangle, the derivative frame tilts each normal the wrong way. The normal texture test's quad
// with every TANGENT (0, 1, 0, -1): +y, a quarter turn about the normal from the derivative frame's
// +x, and w = -1 (a mirrored UV island's handedness). The bitangent is then cross(normal, tangent)
// x w = +x: each pixel against the CPU reference lit with the texel's normal in that frame, at
// least 500 of them far from the derivative frame's. Tricky because ignoring w turns every tilt
// along the bitangent round.
TEST_F(MaterialTexturesTest, TheTangentAttributeIsTheNormalTexturesFrame) {
  tangent_ = glm::vec4(0.0f, 1.0f, 0.0f, -1.0f);
  expectCheckerQuad(
      R"("normalTexture": {"index": 1, "scale": 0.8},)", "", {0.3f, 0.5f, 1.0f},
      [&](const CheckerPixel& p) {
        return std::pair(lit(p, 0.6, 1.0, tiltedNormal(p.at, {0, 1, 0}, {1, 0, 0}, {0, 0, 1})),
                         lit(p, 0.6, 1.0, tiltedNormal(p.at, {1, 0, 0}, {0, 1, 0}, {0, 0, 1})));
      },
      normalMap());
}

// Why: a mirrored instance (glTF: a negative scale) of a mesh with tangents keeps the texture's
// directions on its surface: the tangent moves with the model matrix, but the bitangent
// cross(normal, tangent) * w turns round with the mirror unless w does too. The TANGENT quad with
// every TANGENT (0, 1, 0, 1), its node scaled by (-1, 1, 1): the tangent stays +y, the bitangent
// -x of the unmirrored quad is +x mirrored; each pixel against the CPU reference with that frame,
// at least 500 of them far from the frame whose bitangent did not turn (-x).
TEST_F(MaterialTexturesTest, TheTangentFrameOfAMirroredInstanceKeepsItsHandedness) {
  tangent_ = glm::vec4(0.0f, 1.0f, 0.0f, 1.0f);
  mirrored_ = true;
  expectCheckerQuad(
      R"("normalTexture": {"index": 1, "scale": 0.8},)", "", {0.3f, 0.5f, 1.0f},
      [&](const CheckerPixel& p) {
        return std::pair(lit(p, 0.6, 1.0, tiltedNormal(p.at, {0, 1, 0}, {1, 0, 0}, {0, 0, 1})),
                         lit(p, 0.6, 1.0, tiltedNormal(p.at, {0, 1, 0}, {-1, 0, 0}, {0, 0, 1})));
      },
      normalMap());
}

// glTF alphaMode BLEND: blended meshes drawn over the finished opaque frame, back to front.
class BlendedMeshTest : public MeshMaterialTest {
 protected:
  // A square of side `side` in the plane z = `z` facing +Z, of `material` (its alphaBlend, colour
  // and alpha), placed through the importer's path.
  void addSquare(double z, float side, const glm::vec4& color, bool blend) {
    scene::MaterialData material;
    material.baseColor = color;
    material.roughness = 0.4f;
    material.alphaBlend = blend;
    const glm::mat4 model = glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, float(z))), glm::vec3(side));
    EXPECT_EQ(instantiateNode(square(), model, material).alphaBlend, blend) << "the material's mode reaches the draw";
  }

  // An opaque square of `color` (side `side`) at height z behind what the test placed, and the
  // frame `camera` sees.
  Frame renderOverBackdrop(const glm::dvec3& color, double z, float side, const render::CameraView& camera) {
    addSquare(z, side, glm::vec4(glm::vec3(color), 1.0f), false);
    return render(camera);
  }

  // shadeSurface of a square facing +Z (roughness 0.4, addSquare's) at the ray's point at height z.
  glm::dvec3 squareLit(const glm::dvec3& color, const render::CameraView& camera, std::uint32_t size, glm::vec2 centre,
                       double z) const {
    return referenceShading(desc_, color, 0.4, glm::dvec3(camera.position), pixelRayAtZ(camera, size, centre, z),
                            {0.0, 0.0, 1.0});
  }
};

// glTF's "over" with a straight alpha: what a blended surface of colour `over` and alpha `alpha`
// leaves over `under` (linear colours).
glm::dvec3 blendOver(const glm::dvec3& over, double alpha, const glm::dvec3& under) { return alpha * over + (1.0 - alpha) * under; }

// Whether the ray through `centre` meets the square of side `side` centred on the Z axis at height z.
bool insideSquare(const render::CameraView& camera, std::uint32_t size, glm::vec2 centre, double z, double side) {
  const glm::dvec3 p = pixelRayAtZ(camera, size, centre, z);
  return std::abs(p.x) < 0.5 * side && std::abs(p.y) < 0.5 * side;
}

// Whether the pixel and its four corners all lie on the same side of each square's edge: the
// pixels a comparison calls (rasterization may go either way across an edge).
bool clearOfEdges(const render::CameraView& camera, std::uint32_t size, glm::vec2 centre,
                  const std::vector<std::pair<double, double>>& squares) {
  for (const auto& [z, side] : squares) {
    const bool in = insideSquare(camera, size, centre, z, side);
    for (const glm::vec2 offset : {glm::vec2(-0.5f, -0.5f), glm::vec2(0.5f, -0.5f), glm::vec2(-0.5f, 0.5f), glm::vec2(0.5f, 0.5f)})
      if (insideSquare(camera, size, centre + offset, z, side) != in) return false;
  }
  return true;
}

// Why: a glass pane (glTF alphaMode BLEND) shows what lies behind it through its alpha, the
// factor's times the texture's. The checker quad (BLEND, factor alpha 0.8) has even texels of
// alpha 0.8 and odd ones of 0.8 x 0.6 = 0.48, 0.4 in front of a red square; every pixel must be
// the quad's lit texel times the factor (the CPU reference) blended over the square's lit colour
// by that alpha. Tricky because the quad must not be in the depth prepass (the square behind it
// would fail the depth test: the background, or the quad drawn opaque), must be drawn after the
// square's shading, must blend in linear colour (the target is sRGB), and the alpha is the
// product (the factor's alone gives 0.8 on odd texels, the texture's alone 0.6). The depth and the
// visibility buffer under the quad stay the square's. Tolerance: kColourTolerance, as the opaque
// references; a blend of two colours each within it is within it.
TEST_F(BlendedMeshTest, ABlendedCheckerQuadIsBlendedOverWhatLiesBehindIt) {
  const std::uint32_t size = 96;
  createLitRenderer(size, {0.3f, 0.5f, 1.0f});
  const hsdftest::ScopedTempPath folder("blended_quad");
  const glm::vec4 factor(1.0f, 0.8f, 0.6f, 0.8f);
  const auto data = scene::loadGltf(writeCheckerQuad(folder.path(), factor, R"("alphaMode": "BLEND", )", true));
  ASSERT_TRUE(data.ok()) << data.error().message;
  const render::InstantiatedScene scene = render::instantiateScene(*data, registry_, *pool_);
  ASSERT_EQ(scene.renderables.size(), 1u);
  const glm::dvec3 backColor(0.55, 0.1, 0.08);
  const double backZ = -0.4;
  const glm::vec3 eye(0.0f, 0.0f, 1.6f);
  const render::CameraView camera = render::CameraView::lookAt(eye, {0.0f, 0.0f, 0.0f}, 0.8f, kZNear, 1.0f);
  const Frame frame = renderOverBackdrop(backColor, backZ, 3.0f, camera);
  const std::vector<glm::uvec2> visibility = renderer_->readbackVisibility();
  // The square fills the frame: the corner sees it alone.
  const std::uint32_t squareId = visibility.at(0).x;
  ASSERT_NE(squareId, 0u);
  const glm::dmat4 viewProj = glm::dmat4(camera.proj) * glm::dmat4(camera.view);
  int even = 0, odd = 0, wrong = 0, wrongDepth = 0, notTheSquare = 0;
  double worst = 0.0;
  forEachCheckerPixel(camera, size, [&](std::uint32_t x, std::uint32_t y, glm::ivec2 texel, glm::vec2 centre) {
    const glm::u8vec4 t = checkerTexel(texel.x, texel.y, true);
    const double alpha = double(factor.a) * (t.a / 255.0);
    const glm::dvec3 quad = referenceShading(desc_, linearColor(t) * glm::dvec3(factor), 0.6, glm::dvec3(eye),
                                             pixelRayAtZ(camera, size, centre, 0.0), {0.0, 0.0, 1.0});
    const glm::dvec3 expected = blendOver(quad, alpha, squareLit(backColor, camera, size, centre, backZ));
    const double error = glm::length(linearColor(frame.pixel(x, y)) - expected);
    worst = std::max(worst, error);
    wrong += error > kColourTolerance;
    const glm::dvec4 clip = viewProj * glm::dvec4(pixelRayAtZ(camera, size, centre, backZ), 1.0);
    wrongDepth += std::abs(double(frame.depthAt(x, y)) - clip.z / clip.w) > DeviceTolerances{}.meshDepthAbsolute;
    notTheSquare += visibility[std::size_t(y) * size + x].x != squareId;
    ++(t.a == 255 ? even : odd);
  });
  std::printf("even texels %d pixels, odd %d, wrong %d (worst %.3f), depth not the square's %d, visibility not the "
              "square %d\n",
              even, odd, wrong, worst, wrongDepth, notTheSquare);
  EXPECT_GT(even, 1000);
  EXPECT_GT(odd, 1000);
  EXPECT_EQ(wrong, 0) << "pixels unlike the quad blended over the square (worst colour error " << worst << ")";
  EXPECT_EQ(wrongDepth, 0) << "the blended quad wrote depth: it hides what lies behind it";
  EXPECT_EQ(notTheSquare, 0) << "the visibility buffer names the blended quad";
}

// Why: blended surfaces are drawn back to front, or the far one is blended over the near one
// (with alpha 0.5 each, green over blue over red differs from blue over green over red by a
// quarter of green minus blue). Two overlapping panes at z = 0 and -0.3 before an opaque red square
// at -0.6, added to the scene in both orders: each frame must be the near pane over the far one
// over the square where they overlap, one pane over the square where only it is. Tricky because
// the order in which the file (or the registry) lists them must not matter: the mesh feature sorts
// them on the CPU each frame by their view distance.
TEST_F(BlendedMeshTest, OverlappingBlendedQuadsAreDrawnBackToFrontWhateverTheirOrder) {
  const std::uint32_t size = 96;
  const glm::dvec3 red(0.6, 0.1, 0.1), green(0.1, 0.7, 0.1), blue(0.1, 0.2, 0.8);
  const double nearZ = 0.0, farZ = -0.3, backZ = -0.6, paneSide = 1.0;
  const glm::vec3 eye(0.25f, 0.2f, 1.8f);
  const render::CameraView camera = render::CameraView::lookAt(eye, {0.0f, 0.0f, 0.0f}, 0.8f, kZNear, 1.0f);
  for (const bool nearFirst : {true, false}) {
    SCOPED_TRACE(nearFirst ? "the near pane added first" : "the far pane added first");
    registry_.clear();
    createLitRenderer(size, {0.3f, 0.5f, 1.0f});
    addSquare(backZ, 3.0f, glm::vec4(glm::vec3(red), 1.0f), false);
    if (nearFirst) addSquare(nearZ, float(paneSide), glm::vec4(glm::vec3(green), 0.5f), true);
    addSquare(farZ, float(paneSide), glm::vec4(glm::vec3(blue), 0.5f), true);
    if (!nearFirst) addSquare(nearZ, float(paneSide), glm::vec4(glm::vec3(green), 0.5f), true);
    const Frame frame = render(camera);
    int both = 0, wrong = 0;
    double worst = 0.0;
    for (std::uint32_t y = 0; y < size; ++y) {
      for (std::uint32_t x = 0; x < size; ++x) {
        const glm::vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
        if (!clearOfEdges(camera, size, centre, {{nearZ, paneSide}, {farZ, paneSide}, {backZ, 3.0}}) ||
            !insideSquare(camera, size, centre, backZ, 3.0))
          continue;
        glm::dvec3 expected = squareLit(red, camera, size, centre, backZ);
        const bool inFar = insideSquare(camera, size, centre, farZ, paneSide);
        const bool inNear = insideSquare(camera, size, centre, nearZ, paneSide);
        if (inFar) expected = blendOver(squareLit(blue, camera, size, centre, farZ), 0.5, expected);
        if (inNear) expected = blendOver(squareLit(green, camera, size, centre, nearZ), 0.5, expected);
        const double error = glm::length(linearColor(frame.pixel(x, y)) - expected);
        worst = std::max(worst, error);
        wrong += error > kColourTolerance;
        both += inFar && inNear;
      }
    }
    std::printf("%s: %d pixels through both panes, wrong %d (worst %.3f)\n", nearFirst ? "near first" : "far first", both,
                wrong, worst);
    EXPECT_GT(both, 1000);
    EXPECT_EQ(wrong, 0) << "pixels unlike the panes blended back to front (worst colour error " << worst << ")";
  }
}

// Why: a blended pane behind an opaque object is hidden by it: it tests against the prepass depth
// (it writes none), and where the opaque square in front covers it, the frame is the square's lit
// colour alone; around the square the pane is blended over the background. The normals and depth
// views show the surfaces of the depth buffer, which the pane is not in: there the pane is not
// drawn at all, those frames equal the ones without it.
TEST_F(BlendedMeshTest, ABlendedQuadBehindAnOpaqueSquareIsHidden) {
  const std::uint32_t size = 96;
  createLitRenderer(size, {0.3f, 0.5f, 1.0f});
  const glm::dvec3 white(0.5, 0.45, 0.4), blue(0.1, 0.2, 0.8);  // lit below 1: the UNORM target clamps nothing
  const double frontZ = 0.0, paneZ = -0.4;
  addSquare(frontZ, 1.0f, glm::vec4(glm::vec3(white), 1.0f), false);
  const glm::vec3 eye(0.0f, 0.0f, 1.6f);
  const render::CameraView camera = render::CameraView::lookAt(eye, {0.0f, 0.0f, 0.0f}, 0.8f, kZNear, 1.0f);
  scene::updateWorldTransforms(registry_);
  const Frame normalsAlone = renderWith(camera, DEBUG_VIEW_NORMALS);
  const Frame depthAlone = renderWith(camera, DEBUG_VIEW_DEPTH);
  addSquare(paneZ, 2.0f, glm::vec4(glm::vec3(blue), 0.5f), true);
  const Frame frame = render(camera);
  const glm::dvec3 background(desc_.clearColor);
  int hidden = 0, around = 0, wrong = 0;
  double worst = 0.0;
  for (std::uint32_t y = 0; y < size; ++y) {
    for (std::uint32_t x = 0; x < size; ++x) {
      const glm::vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
      if (!clearOfEdges(camera, size, centre, {{frontZ, 1.0}, {paneZ, 2.0}})) continue;
      glm::dvec3 expected;
      if (insideSquare(camera, size, centre, frontZ, 1.0)) {
        expected = squareLit(white, camera, size, centre, frontZ);
        ++hidden;
      } else if (insideSquare(camera, size, centre, paneZ, 2.0)) {
        expected = blendOver(squareLit(blue, camera, size, centre, paneZ), 0.5, background);
        ++around;
      } else {
        continue;
      }
      const double error = glm::length(linearColor(frame.pixel(x, y)) - expected);
      worst = std::max(worst, error);
      wrong += error > kColourTolerance;
    }
  }
  std::printf("hidden %d pixels, around the square %d, wrong %d (worst %.3f)\n", hidden, around, wrong, worst);
  EXPECT_GT(hidden, 1000);
  EXPECT_GT(around, 1000);
  EXPECT_EQ(wrong, 0) << "pixels unlike the square in front, or the pane over the background (worst " << worst << ")";
  scene::updateWorldTransforms(registry_);
  EXPECT_EQ(differingPixels(renderWith(camera, DEBUG_VIEW_NORMALS), normalsAlone), 0u) << "the normals view drew the pane";
  EXPECT_EQ(differingPixels(renderWith(camera, DEBUG_VIEW_DEPTH), depthAlone), 0u) << "the depth view drew the pane";
}

// Why: a double-sided blended mesh (a glass box, a bottle) shows its far side through its near
// side. glTF leaves the order of a mesh's triangles undefined; the mesh feature draws a double-sided
// blended mesh's back faces, then its front faces, so that through a convex one the near side lies
// over the far side, each lit as the side seen (a back face with its normal reversed). A closed
// cube (alpha 0.5) before an opaque red square, seen from above at a slant: every pixel through it
// must be its front face over its back face over the square. Tricky because the cube is one draw
// (one object: sorting objects does not order its faces), and because through the cube's top or
// front the eye sees the inside of another face, lit unlike the face in front (the light grazes),
// so the wrong order shows (discriminating pixels).
TEST_F(BlendedMeshTest, ADoubleSidedBlendedCubeShowsItsBackFacesBehindItsFrontFaces) {
  const std::uint32_t size = 96;
  createLitRenderer(size, {0.9f, 0.3f, 0.2f});
  scene::MeshPrimitiveData cube = openBox();
  cube.indices.insert(cube.indices.end(), {2, 6, 3, 3, 6, 7});  // the lid: +Y
  const glm::vec4 color(0.9f, 0.7f, 0.3f, 0.5f);
  const glm::mat4 model = glm::rotate(glm::mat4(1.0f), 0.4f, glm::vec3(0.0f, 1.0f, 0.0f));
  scene::MaterialData material;
  material.baseColor = color;
  material.roughness = 0.4f;
  material.doubleSided = true;
  material.alphaBlend = true;
  instantiateNode(cube, model, material);
  const Surface surface = place(cube, model, true);
  const glm::dvec3 red(0.6, 0.1, 0.1);
  const double backZ = -1.5;
  const glm::vec3 eye(0.8f, 1.6f, 2.4f);
  const render::CameraView camera = render::CameraView::lookAt(eye, {0.0f, 0.0f, 0.0f}, 0.8f, kZNear, 1.0f);
  const Frame frame = renderOverBackdrop(red, backZ, 8.0f, camera);
  // Each side as the frame lights it: the side seen, its normal reversed on a back face.
  auto lit = [&](const math::Ray& ray, const Hit& hit) {
    const glm::dvec3 n = surface.normals[std::size_t(hit.triangle)];
    return referenceShading(desc_, glm::dvec3(color), 0.4, glm::dvec3(eye), ray.origin + hit.t * ray.direction,
                            hit.backFace ? -n : n);
  };
  int through = 0, discriminating = 0, wrong = 0;
  double worst = 0.0;
  for (std::uint32_t y = 0; y < size; ++y) {
    for (std::uint32_t x = 0; x < size; ++x) {
      const glm::vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
      auto triangles = [&](glm::vec2 pixel) {
        std::vector<int> seen;
        for (const Hit& h : castAll(surface, math::pixelRay(camera.view, camera.proj, pixel, glm::ivec2(int(size)))))
          seen.push_back(h.triangle);
        return seen;
      };
      const std::vector<int> seen = triangles(centre);
      bool edge = false;
      for (const glm::vec2 offset : {glm::vec2(-0.5f, -0.5f), glm::vec2(0.5f, -0.5f), glm::vec2(-0.5f, 0.5f), glm::vec2(0.5f, 0.5f)})
        edge = edge || triangles(centre + offset) != seen;
      if (edge || seen.empty()) continue;
      const math::Ray ray = math::pixelRay(camera.view, camera.proj, centre, glm::ivec2(int(size)));
      const std::vector<Hit> hits = castAll(surface, ray);
      ASSERT_EQ(hits.size(), 2u) << "a ray through a convex cube meets two faces";
      ASSERT_FALSE(hits[0].backFace);
      ASSERT_TRUE(hits[1].backFace);
      const glm::dvec3 behind = squareLit(red, camera, size, centre, backZ);
      const glm::dvec3 front = lit(ray, hits[0]), back = lit(ray, hits[1]);
      const glm::dvec3 expected = blendOver(front, color.a, blendOver(back, color.a, behind));
      const glm::dvec3 reversed = blendOver(back, color.a, blendOver(front, color.a, behind));
      const double error = glm::length(linearColor(frame.pixel(x, y)) - expected);
      worst = std::max(worst, error);
      wrong += error > kColourTolerance;
      discriminating += glm::length(reversed - expected) > 2.0 * kColourTolerance;
      ++through;
    }
  }
  std::printf("through the cube %d pixels (discriminating %d), wrong %d (worst %.3f)\n", through, discriminating, wrong,
              worst);
  EXPECT_GT(through, 1500);
  EXPECT_GT(discriminating, 150) << "the view must tell the back faces drawn first from last";
  EXPECT_EQ(wrong, 0) << "pixels unlike the front faces over the back faces over the square (worst " << worst << ")";
}

}  // namespace
}  // namespace gputest
