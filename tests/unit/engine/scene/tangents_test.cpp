// Tangents made for a normal texture when a file gives none (engine/scene/tangents.h), against
// closed forms: a latitude-longitude sphere, whose +u direction is the local east, and flat quads
// whose texture is turned or mirrored.
#include "engine/scene/tangents.h"

#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/constants.hpp>

namespace engine::scene {
namespace {

constexpr double kPi = glm::pi<double>();

// The unit sphere P(u, v) = (sin t cos p, sin t sin p, cos t), p = 2 pi u, t = pi v: rows of
// `rows` + 1 vertices from pole to pole, `columns` + 1 around (the seam's column doubled, as an
// exporter splits it).
MeshPrimitiveData uvSphere(int rows, int columns) {
  MeshPrimitiveData sphere;
  for (int r = 0; r <= rows; ++r)
    for (int c = 0; c <= columns; ++c) {
      const double t = kPi * r / rows, p = 2.0 * kPi * c / columns;
      const glm::vec3 point(float(std::sin(t) * std::cos(p)), float(std::sin(t) * std::sin(p)), float(std::cos(t)));
      sphere.positions.push_back(point);
      sphere.normals.push_back(point);
      sphere.texcoords.emplace_back(float(c) / float(columns), float(r) / float(rows));
    }
  const auto at = [columns](int r, int c) { return std::uint32_t(r * (columns + 1) + c); };
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < columns; ++c) {
      if (r > 0) sphere.indices.insert(sphere.indices.end(), {at(r, c), at(r + 1, c), at(r, c + 1)});
      if (r + 1 < rows) sphere.indices.insert(sphere.indices.end(), {at(r, c + 1), at(r + 1, c), at(r + 1, c + 1)});
    }
  return sphere;
}

// A unit quad in z = 0 (normal +z) with texcoords uv(x, y) at its corners.
template <class Uv>
MeshPrimitiveData quad(Uv uv) {
  MeshPrimitiveData q;
  for (const glm::vec2 corner : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)}) {
    q.positions.emplace_back(corner, 0.0f);
    q.normals.emplace_back(0.0f, 0.0f, 1.0f);
    q.texcoords.push_back(uv(corner));
  }
  q.indices = {0, 1, 2, 0, 2, 3};
  return q;
}

double degreesBetween(glm::dvec3 a, glm::dvec3 b) {
  return glm::degrees(std::acos(glm::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)));
}

// Tricky: every triangle's own +u direction is a chord, off the vertex's east by half a column's
// turn; the corners around a vertex must cancel that, and the bitangent toward -v (glTF's v runs
// down the image) is north here, where v grows southward: w = +1 where cross(n, t) is north.
TEST(Tangents, ALatitudeLongitudeSphereGetsItsEastAndNorth) {
  const MeshPrimitiveData sphere = uvSphere(16, 32);
  const auto tangents = generateTangents(sphere);
  ASSERT_TRUE(tangents) << tangents.error().message;
  // The seam's columns see triangles on one side only (its vertices are split, as MikkTSpace's
  // are by their texcoords): a one-sided chord, half a column (5.6 degrees) off at most.
  double worst = 0.0, worstSeam = 0.0;
  for (int r = 1; r < 16; ++r)
    for (int c = 0; c <= 32; ++c) {
      const bool seam = c == 0 || c == 32;
      const std::size_t i = std::size_t(r * 33 + c);
      const double p = 2.0 * kPi * c / 32;
      const glm::dvec3 east(-std::sin(p), std::cos(p), 0.0);
      const glm::vec4 t = (*tangents)[i];
      double& off = seam ? worstSeam : worst;
      off = std::max(off, degreesBetween(glm::dvec3(t), east));
      EXPECT_NEAR(glm::dot(glm::vec3(t), sphere.normals[i]), 0.0f, 1e-5f) << "in the normal's plane";
      // North, toward -v: -dP/dt = (-cos t cos p, -cos t sin p, sin t).
      const double theta = kPi * r / 16;
      const glm::dvec3 north(-std::cos(theta) * std::cos(p), -std::cos(theta) * std::sin(p), std::sin(theta));
      const glm::dvec3 bitangent = glm::cross(glm::dvec3(sphere.normals[i]), glm::dvec3(t)) * double(t.w);
      EXPECT_LT(degreesBetween(bitangent, north), seam ? 5.7 : 0.01) << "row " << r << " column " << c;
    }
  EXPECT_LT(worst, 0.01) << "degrees from the east";
  EXPECT_LT(worstSeam, 5.7) << "degrees from the east on the seam";
}

// Tricky: the tangent follows the texture, not the mesh: a texture turned a quarter has +u along
// +y; one mirrored in u has +u along -x and the opposite handedness (an exporter's mirrored half).
TEST(Tangents, ATurnedOrMirroredTextureTurnsOrMirrorsTheFrame) {
  const auto plain = generateTangents(quad([](glm::vec2 p) { return p; }));
  const auto turned = generateTangents(quad([](glm::vec2 p) { return glm::vec2(p.y, 1.0f - p.x); }));
  const auto mirrored = generateTangents(quad([](glm::vec2 p) { return glm::vec2(1.0f - p.x, p.y); }));
  ASSERT_TRUE(plain && turned && mirrored);
  for (std::size_t i = 0; i < 4; ++i) {
    // Plain: u along +x, v along +y, so -v is -y = cross(+z, +x) * -1.
    EXPECT_EQ((*plain)[i], glm::vec4(1.0f, 0.0f, 0.0f, -1.0f));
    EXPECT_EQ((*turned)[i], glm::vec4(0.0f, 1.0f, 0.0f, -1.0f));
    EXPECT_EQ((*mirrored)[i], glm::vec4(-1.0f, 0.0f, 0.0f, 1.0f));
  }
}

// Tricky: texcoords of zero area give no direction at all; the caller must know (and keep the
// derivative frame) rather than draw with a made-up tangent. One such triangle beside good ones
// takes nothing from its vertices.
TEST(Tangents, TexcoordsOfZeroAreaAreRefusedNamingTheVertices) {
  const auto flat = generateTangents(quad([](glm::vec2) { return glm::vec2(0.5f); }));
  ASSERT_FALSE(flat);
  EXPECT_NE(flat.error().message.find("4 of 4 vertices have no texture direction"), std::string::npos)
      << flat.error().message;

  MeshPrimitiveData q = quad([](glm::vec2 p) { return p; });
  q.positions.emplace_back(2.0f, 0.0f, 0.0f);
  q.normals.emplace_back(0.0f, 0.0f, 1.0f);
  q.texcoords.emplace_back(1.0f, 0.0f);  // on the line of corners 1 and 2: zero area
  q.indices.insert(q.indices.end(), {1, 4, 2});
  const auto mixed = generateTangents(q);
  ASSERT_FALSE(mixed) << "vertex 4 has no direction";
  q.texcoords.back() = glm::vec2(2.0f, 0.0f);
  const auto good = generateTangents(q);
  ASSERT_TRUE(good) << good.error().message;
  EXPECT_EQ((*good)[1], glm::vec4(1.0f, 0.0f, 0.0f, -1.0f));

  MeshPrimitiveData short_ = quad([](glm::vec2 p) { return p; });
  short_.texcoords.pop_back();
  EXPECT_FALSE(generateTangents(short_));
}

}  // namespace
}  // namespace engine::scene
