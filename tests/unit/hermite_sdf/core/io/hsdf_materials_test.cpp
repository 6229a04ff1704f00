// .hsdf material sections (docs/hsdf-format.md, "Materials"): a multi-material field saves and
// loads its palette and slots; a field of one material writes the bytes it always did; every
// malformed section is refused naming the problem.
#include <cmath>
#include <functional>
#include <limits>

#include <gtest/gtest.h>

#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/hsdf_file.h"

namespace hsdf {
namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr std::size_t kFlagsAt = 24, kPayloadBytesAt = 80;

// A sphere at K = 8, both payloads, with a slot per sample (1 above the sphere's centre, 0 below;
// 2 for the samples of the highest layer, so that three entries are used) and a palette of three.
HsdfContents multiMaterialSphere(HsdfScalarType type = HsdfScalarType::Float32, bool dense = true, bool cells = true) {
  const SphereSource sphere(glm::dvec3(0.1, -0.05, 0.02), 0.8);
  const GridSpec grid = fitGrid(sphere.bounds(), 8, 1).value();
  HermiteField field = bakeHermiteField(sphere, grid).value();
  field.materials.resize(field.samples.size());
  for (int k = 0; k < grid.resolution; ++k)
    for (int j = 0; j < grid.resolution; ++j)
      for (int i = 0; i < grid.resolution; ++i)
        field.materials[grid.sampleIndex(i, j, k)] =
            j == grid.resolution - 1 ? 2 : (grid.samplePosition(i, j, k).y > -0.05 ? 1 : 0);
  const CellClassification classes = classifyCells(field).value();
  HsdfContents contents;
  contents.grid = grid;
  contents.scalarType = type;
  if (cells) contents.cells = extractCells(field, classes).value();
  if (dense) contents.dense = std::move(field);
  contents.palette = {{{0.9f, 0.1f, 0.1f, 1.0f}, 0.3f, 0.0f}, {{0.1f, 0.2f, 0.9f, 1.0f}, 0.6f, 0.5f},
                      {{0.2f, 0.8f, 0.3f, 1.0f}, 0.9f, 1.0f}};
  return contents;
}

Bytes serialize(const HsdfContents& contents) {
  auto bytes = serializeHsdf(contents);
  EXPECT_TRUE(bytes.ok()) << (bytes.ok() ? "" : bytes.error().message);
  return bytes.ok() ? *bytes : Bytes{};
}

std::string loadError(const Bytes& bytes) {
  auto loaded = loadHsdfFromMemory(bytes);
  return loaded.ok() ? std::string("(loaded)") : loaded.error().message;
}

void put32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.at(at + std::size_t(i)) = std::uint8_t(v >> (8 * i));
}
void put64(Bytes& b, std::size_t at, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) b.at(at + std::size_t(i)) = std::uint8_t(v >> (8 * i));
}
std::uint64_t get64(const Bytes& b, std::size_t at) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= std::uint64_t(b.at(at + std::size_t(i))) << (8 * i);
  return v;
}
void refreshChecksum(Bytes& b) { put64(b, b.size() - 8, hsdfChecksum(std::span(b).first(b.size() - 8))); }
bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Where the material section starts: after the header, the dense samples and the records.
std::size_t materialsAt(const HsdfContents& c) {
  const std::size_t s = c.scalarType == HsdfScalarType::Float16 ? 2 : 4;
  return 96 + (c.dense ? c.dense->samples.size() * 4 * s : 0) + (c.cells ? c.cells->records.size() * (8 + 32 * s) : 0);
}

// Tricky: the slots ride beside payloads of either precision and either kind; a reader that takes
// the cells' slots from where a dense-only file's would be, or drops the palette's roughness and
// metallic, differs here.
TEST(HsdfMaterials, RoundTripKeepsPaletteAndSlots) {
  for (const HsdfScalarType type : {HsdfScalarType::Float32, HsdfScalarType::Float16})
    for (const auto& [dense, cells] : {std::pair{true, true}, std::pair{true, false}, std::pair{false, true}}) {
      const HsdfContents original = multiMaterialSphere(type, dense, cells);
      auto loaded = loadHsdfFromMemory(serialize(original));
      ASSERT_TRUE(loaded.ok()) << loaded.error().message;
      EXPECT_EQ(loaded->palette, original.palette);
      ASSERT_EQ(bool(loaded->dense), dense);
      ASSERT_EQ(bool(loaded->cells), cells);
      if (dense) {
        EXPECT_EQ(loaded->dense->materials, original.dense->materials);
      }
      if (cells) {
        EXPECT_EQ(loaded->cells->materials, original.cells->materials);
      }
    }
}

// Files of one material are what they were before materials existed: no flag, no section, the
// version 1 payload size; and a file of those bytes loads with no palette and no slots.
TEST(HsdfMaterials, OneMaterialKeepsTheOldBytes) {
  HsdfContents contents = multiMaterialSphere();
  contents.palette.clear();
  contents.dense->materials.clear();
  contents.cells->materials.clear();
  const Bytes bytes = serialize(contents);
  ASSERT_FALSE(bytes.empty());
  EXPECT_EQ(bytes[kFlagsAt], 3u);  // dense | cells, as version 1 always wrote
  EXPECT_EQ(get64(bytes, kPayloadBytesAt), contents.dense->samples.size() * 16 + contents.cells->records.size() * 136);
  EXPECT_EQ(bytes.size(), 96 + get64(bytes, kPayloadBytesAt) + 8);
  auto loaded = loadHsdfFromMemory(bytes);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_TRUE(loaded->palette.empty());
  EXPECT_TRUE(loaded->dense->materials.empty());
  EXPECT_TRUE(loaded->cells->materials.empty());
  // The multi-material file is the same file plus its section.
  const HsdfContents multi = multiMaterialSphere();
  const Bytes withMaterials = serialize(multi);
  ASSERT_EQ(withMaterials.size(), bytes.size() + 8 + 3 * 24 + multi.dense->samples.size() + 8 * multi.cells->records.size());
  EXPECT_TRUE(std::equal(bytes.begin() + 96, bytes.end() - 8, withMaterials.begin() + 96));
}

// Tricky: each malformed section must be refused before its values are trusted, with the checksum
// made valid again so that the section's own check is what refuses it (a corrupted file fails the
// checksum first, which says nothing of the section).
TEST(HsdfMaterials, MalformedSectionsAreRefusedNamingTheProblem) {
  const HsdfContents original = multiMaterialSphere();
  const Bytes good = serialize(original);
  ASSERT_FALSE(good.empty());
  const std::size_t at = materialsAt(original);
  const std::size_t slotsAt = at + 8 + 3 * 24;
  const auto edited = [&](const std::function<void(Bytes&)>& edit) {
    Bytes b = good;
    edit(b);
    refreshChecksum(b);
    return loadError(b);
  };
  EXPECT_TRUE(contains(edited([&](Bytes& b) { put32(b, at, 1); }), "a palette of 1 materials"));
  EXPECT_TRUE(contains(edited([&](Bytes& b) { put32(b, at, 300); }), "a palette of 300 materials"));
  // A palette size that does not match the bytes: the payload size no longer matches.
  EXPECT_TRUE(contains(edited([&](Bytes& b) { put32(b, at, 4); }), "payload size"));
  EXPECT_TRUE(contains(edited([&](Bytes& b) { put32(b, at + 4, 7); }), "reserved field is not zero"));
  EXPECT_TRUE(contains(edited([&](Bytes& b) { put32(b, at + 8, 0x7fc00000u); }), "palette entry 0 is not finite"));
  EXPECT_TRUE(contains(edited([&](Bytes& b) { b.at(slotsAt + 5) = 3; }), "material slot 3 at entry 5 is past the palette"));
  // A cell's corner slot unlike the dense sample's (still within the palette).
  const std::size_t cellSlotsAt = slotsAt + original.dense->samples.size();
  const std::string mismatch = edited([&](Bytes& b) { b.at(cellSlotsAt + 2) = std::uint8_t((b.at(cellSlotsAt + 2) + 1) % 3); });
  EXPECT_TRUE(contains(mismatch, "cell record 0")) << mismatch;
  EXPECT_TRUE(contains(mismatch, "corner 2 has material slot")) << mismatch;
  // The flag set on a file without the section: where the palette size would be is the checksum.
  const std::string truncated = edited([&](Bytes& b) {
    b.resize(at + 8);
    b.at(kFlagsAt) = 7;
    put64(b, kPayloadBytesAt, at - 96);
  });
  EXPECT_TRUE(contains(truncated, "ends before its material section")) << truncated;
  // The section alone, with neither payload.
  EXPECT_TRUE(contains(edited([&](Bytes& b) { b.at(kFlagsAt) = 4; }), "no payload"));
  EXPECT_TRUE(contains(edited([&](Bytes& b) { b.at(kFlagsAt) = 15; }), "unknown flags 0xf"));
}

// The writer refuses what the reader would: slots without a palette, a palette without slots,
// slots past the palette, a palette that is not finite, a palette of one.
TEST(HsdfMaterials, SerializeRefusesInconsistentMaterials) {
  const auto error = [](const HsdfContents& c) {
    auto bytes = serializeHsdf(c);
    return bytes.ok() ? std::string("(serialized)") : bytes.error().message;
  };
  HsdfContents noPalette = multiMaterialSphere();
  noPalette.palette.clear();
  EXPECT_TRUE(contains(error(noPalette), "material slots but there is no palette")) << error(noPalette);
  HsdfContents noSlots = multiMaterialSphere();
  noSlots.cells->materials.clear();
  EXPECT_TRUE(contains(error(noSlots), "0 material slot entries")) << error(noSlots);
  HsdfContents past = multiMaterialSphere();
  past.dense->materials[9] = 3;
  EXPECT_TRUE(contains(error(past), "past the palette")) << error(past);
  HsdfContents nan = multiMaterialSphere();
  nan.palette[1].roughness = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(contains(error(nan), "palette entry 1 is not finite")) << error(nan);
  HsdfContents one = multiMaterialSphere();
  one.palette.resize(1);
  EXPECT_TRUE(contains(error(one), "a palette of 1 materials")) << error(one);
}

}  // namespace
}  // namespace hsdf
