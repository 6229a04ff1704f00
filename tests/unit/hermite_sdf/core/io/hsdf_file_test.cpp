// .hsdf files: round trips, the documented byte layout, and one test per corruption class.
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include <gtest/gtest.h>

#include "test_files.h"
#include "hermite_sdf/core/analytic.h"
#include "hermite_sdf/core/hsdf_file.h"

namespace hsdf {
namespace {

using Bytes = std::vector<std::uint8_t>;

// A sphere baked at K = 8 with its cell stream: small, but with both cell classes and every
// payload kind.
HsdfContents sphereContents(HsdfScalarType type = HsdfScalarType::Float32, bool dense = true, bool cells = true,
                            double scale = 1.0) {
  const SphereSource sphere(scale * glm::dvec3(0.1, -0.05, 0.02), scale * 0.8);
  const GridSpec grid = fitGrid(sphere.bounds(), 8, 1).value();
  HermiteField field = bakeHermiteField(sphere, grid).value();
  const CellClassification classes = classifyCells(field).value();
  HsdfContents contents;
  contents.grid = grid;
  contents.scalarType = type;
  if (cells) contents.cells = extractCells(field, classes).value();
  if (dense) contents.dense = std::move(field);
  return contents;
}

Bytes serialize(const HsdfContents& contents) {
  auto bytes = serializeHsdf(contents);
  EXPECT_TRUE(bytes.ok()) << (bytes.ok() ? "" : bytes.error().message);
  return bytes.ok() ? *bytes : Bytes{};
}

std::string loadError(const Bytes& bytes, const HsdfLoadOptions& options = {}) {
  auto loaded = loadHsdfFromMemory(bytes, options);
  return loaded.ok() ? std::string("(loaded)") : loaded.error().message;
}

// at(): a failed serialize() leaves the bytes empty; that must fail the test, not write past them.
void put32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.at(at + std::size_t(i)) = std::uint8_t(v >> (8 * i));
}
void put64(Bytes& b, std::size_t at, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) b.at(at + std::size_t(i)) = std::uint8_t(v >> (8 * i));
}
std::uint32_t get32(const Bytes& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= std::uint32_t(b[at + std::size_t(i)]) << (8 * i);
  return v;
}
std::uint64_t get64(const Bytes& b, std::size_t at) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= std::uint64_t(b[at + std::size_t(i)]) << (8 * i);
  return v;
}
// After a deliberate edit: make the checksum valid again so the edit itself is what is tested.
void refreshChecksum(Bytes& b) {
  put64(b, b.size() - 8, hsdfChecksum(std::span(b).first(b.size() - 8)));
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

void expectSameSamples(const HermiteSample& a, const HermiteSample& b) {
  EXPECT_EQ(a.f, b.f);
  EXPECT_EQ(a.fx, b.fx);
  EXPECT_EQ(a.fy, b.fy);
  EXPECT_EQ(a.fz, b.fz);
}

float viaHalf(float v) { return halfToFloat(floatToHalf(v)); }

// Tricky: fp32 must come back bit for bit, including the grid (doubles) and cell classes.
TEST(HsdfFile, RoundTripFloat32) {
  const HsdfContents original = sphereContents();
  ASSERT_GT(original.cells->records.size(), 10u);
  auto loaded = loadHsdfFromMemory(serialize(original));
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(loaded->grid.resolution, original.grid.resolution);
  EXPECT_EQ(loaded->grid.spacing, original.grid.spacing);
  EXPECT_EQ(loaded->grid.origin, original.grid.origin);
  ASSERT_TRUE(loaded->dense && loaded->cells);
  ASSERT_EQ(loaded->dense->samples.size(), original.dense->samples.size());
  for (std::size_t s = 0; s < original.dense->samples.size(); ++s)
    expectSameSamples(loaded->dense->samples[s], original.dense->samples[s]);
  ASSERT_EQ(loaded->cells->records.size(), original.cells->records.size());
  for (std::size_t r = 0; r < original.cells->records.size(); ++r) {
    const CellRecord& a = loaded->cells->records[r];
    const CellRecord& b = original.cells->records[r];
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(a.z, b.z);
    EXPECT_EQ(a.cellClass, b.cellClass);
    for (int c = 0; c < 8; ++c) expectSameSamples(a.corners[std::size_t(c)], b.corners[std::size_t(c)]);
  }
}

// Tricky: fp16 files store rounded scalars; loading must give exactly the rounded values (not the
// originals, not a second rounding), half the payload size, and dense and cells must still agree.
TEST(HsdfFile, RoundTripFloat16) {
  const HsdfContents original = sphereContents(HsdfScalarType::Float16);
  const Bytes bytes = serialize(original);
  const Bytes full = serialize(sphereContents(HsdfScalarType::Float32));
  EXPECT_EQ(bytes.size() - 104, (full.size() - 104 - 8 * original.cells->records.size()) / 2 +
                                    8 * original.cells->records.size());
  auto loaded = loadHsdfFromMemory(bytes);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(loaded->scalarType, HsdfScalarType::Float16);
  for (std::size_t s = 0; s < original.dense->samples.size(); ++s) {
    const HermiteSample& a = original.dense->samples[s];
    expectSameSamples(loaded->dense->samples[s], {viaHalf(a.f), viaHalf(a.fx), viaHalf(a.fy), viaHalf(a.fz)});
  }
  const CellStream expected = toFloat(toHalf(*original.cells));
  for (std::size_t r = 0; r < expected.records.size(); ++r)
    for (int c = 0; c < 8; ++c)
      expectSameSamples(loaded->cells->records[r].corners[std::size_t(c)], expected.records[r].corners[std::size_t(c)]);
}

// Tricky: either payload alone is a valid file; the flags, not the sizes, say which is present.
TEST(HsdfFile, RoundTripSinglePayloads) {
  auto denseOnly = loadHsdfFromMemory(serialize(sphereContents(HsdfScalarType::Float32, true, false)));
  ASSERT_TRUE(denseOnly.ok()) << denseOnly.error().message;
  EXPECT_TRUE(denseOnly->dense && !denseOnly->cells);
  auto cellsOnly = loadHsdfFromMemory(serialize(sphereContents(HsdfScalarType::Float16, false, true)));
  ASSERT_TRUE(cellsOnly.ok()) << cellsOnly.error().message;
  EXPECT_TRUE(!cellsOnly->dense && cellsOnly->cells);
}

// The by-reference contents (what hsdf_bake saves an asset with) must write the very bytes the
// owning contents write, for every payload combination and scalar type, and be checked alike.
TEST(HsdfFile, ViewSerializesTheSameBytes) {
  for (HsdfScalarType type : {HsdfScalarType::Float32, HsdfScalarType::Float16})
    for (int payloads : {1, 2, 3}) {
      const HsdfContents owned = sphereContents(type, payloads & 1, payloads & 2);
      const HsdfContentsView view{owned.grid, owned.scalarType, owned.dense ? &*owned.dense : nullptr,
                                  owned.cells ? &*owned.cells : nullptr};
      auto bytes = serializeHsdf(view);
      ASSERT_TRUE(bytes.ok()) << bytes.error().message;
      EXPECT_EQ(*bytes, serialize(owned)) << "type " << int(type) << " payloads " << payloads;
    }
  HsdfContentsView empty;
  empty.grid = sphereContents().grid;
  EXPECT_FALSE(serializeHsdf(empty).ok()) << "a view without payload must be refused like the contents";
}

// Tricky: outside tools rely on docs/hsdf-format.md; this pins the documented offsets, encodings
// and checksum (test vectors of FNV-1a 64) so the code cannot drift from the document.
TEST(HsdfFile, ByteLayoutMatchesTheSpecification) {
  EXPECT_EQ(hsdfChecksum({}), 0xcbf29ce484222325ULL);
  const std::uint8_t a[] = {'a'};
  EXPECT_EQ(hsdfChecksum(a), 0xaf63dc4c8601ec8cULL);
  const std::uint8_t foobar[] = {'f', 'o', 'o', 'b', 'a', 'r'};
  EXPECT_EQ(hsdfChecksum(foobar), 0x85944171f73967e8ULL);

  const HsdfContents contents = sphereContents();
  const Bytes b = serialize(contents);
  const std::uint8_t magic[8] = {'H', 'S', 'D', 'F', 0x0D, 0x0A, 0x1A, 0x0A};
  EXPECT_EQ(std::memcmp(b.data(), magic, 8), 0);
  EXPECT_EQ(get32(b, 8), 1u);    // version
  EXPECT_EQ(get32(b, 12), 96u);  // header bytes
  EXPECT_EQ(get32(b, 16), 8u);   // K
  EXPECT_EQ(get32(b, 20), 0u);   // fp32
  EXPECT_EQ(get32(b, 24), 3u);   // dense | cells
  EXPECT_EQ(std::bit_cast<double>(get64(b, 32)), contents.grid.spacing);
  EXPECT_EQ(std::bit_cast<double>(get64(b, 40)), contents.grid.origin.x);
  EXPECT_EQ(std::bit_cast<double>(get64(b, 56)), contents.grid.origin.z);
  EXPECT_EQ(get64(b, 64), 512u);
  const std::uint64_t cells = contents.cells->records.size();
  EXPECT_EQ(get64(b, 72), cells);
  EXPECT_EQ(get64(b, 80), 512u * 16u + cells * 136u);
  EXPECT_EQ(b.size(), 96u + 512u * 16u + cells * 136u + 8u);
  // Dense sample 1 = (i=1, j=0, k=0) at byte 96 + 16: f then fx, fy, fz.
  EXPECT_EQ(std::bit_cast<float>(get32(b, 96 + 16)), contents.dense->samples[1].f);
  EXPECT_EQ(std::bit_cast<float>(get32(b, 96 + 16 + 12)), contents.dense->samples[1].fz);
  // First cell record: x, y, z, class as u16, then corner 0's f.
  const std::size_t cellsAt = 96 + 512 * 16;
  const CellRecord& first = contents.cells->records.front();
  EXPECT_EQ(get32(b, cellsAt), std::uint32_t(first.x) | (std::uint32_t(first.y) << 16));
  EXPECT_EQ(std::bit_cast<float>(get32(b, cellsAt + 8)), first.corners[0].f);
  EXPECT_EQ(get64(b, b.size() - 8), hsdfChecksum(std::span(b).first(b.size() - 8)));
}

// Tricky: every truncation point must be refused without reading past the end, from "not even a
// magic" to "one checksum byte missing"; appended bytes are refused too.
TEST(HsdfFile, TruncatedAndOversizedFilesAreRefused) {
  const Bytes full = serialize(sphereContents(HsdfScalarType::Float16));
  for (std::size_t size = 0; size < full.size(); size += (size < 200 ? 1 : 97)) {
    const std::string error = loadError(Bytes(full.begin(), full.begin() + std::ptrdiff_t(size)));
    EXPECT_TRUE(contains(error, size < 8 ? "not an .hsdf file" : "truncated")) << size << ": " << error;
  }
  EXPECT_TRUE(contains(loadError(Bytes(full.begin(), full.end() - 1)), "truncated"));
  Bytes longer = full;
  longer.push_back(0);
  EXPECT_TRUE(contains(loadError(longer), "1 unexpected bytes after the checksum"));
}

// Tricky: a forged header announcing a huge field in a tiny file must fail on sizes, before any
// allocation; a consistent file over the caller's budget must be refused by the budget.
TEST(HsdfFile, ForgedSizesAndBudgetAreRefusedBeforeAllocating) {
  Bytes b = serialize(sphereContents());
  Bytes huge = b;
  put32(huge, 16, 4096);
  put64(huge, 64, std::uint64_t(4096) * 4096 * 4096);
  put64(huge, 80, std::uint64_t(4096) * 4096 * 4096 * 16 + get64(b, 72) * 136);
  refreshChecksum(huge);
  EXPECT_TRUE(contains(loadError(huge), "truncated")) << loadError(huge);

  Bytes overflow = b;
  put64(overflow, 72, std::uint64_t(1) << 62);
  refreshChecksum(overflow);
  EXPECT_TRUE(contains(loadError(overflow), "cell count 4611686018427387904 is impossible")) << loadError(overflow);

  HsdfLoadOptions small;
  small.memoryBudgetBytes = 4096;
  EXPECT_TRUE(contains(loadError(b, small), "over the budget of 4096")) << loadError(b, small);
}

// Tricky: counts that contradict each other (dense count vs K, payload size vs counts, flags vs
// counts) each get their own message, even with a valid checksum.
TEST(HsdfFile, InconsistentCountsAreRefused) {
  const Bytes b = serialize(sphereContents());
  Bytes denseCount = b;
  put64(denseCount, 64, 511);
  refreshChecksum(denseCount);
  EXPECT_TRUE(contains(loadError(denseCount), "dense sample count 511 does not match 512")) << loadError(denseCount);
  Bytes payload = b;
  put64(payload, 80, get64(b, 80) + 8);
  refreshChecksum(payload);
  EXPECT_TRUE(contains(loadError(payload), "does not match the counts")) << loadError(payload);
  Bytes flags = b;
  put32(flags, 24, 1);  // cells flag cleared, cell count still set
  refreshChecksum(flags);
  EXPECT_TRUE(contains(loadError(flags), "is impossible")) << loadError(flags);
}

// Tricky: a file of a later format version may have a different header size, payload layout and
// length, so every check after the magic would fail first and blame the wrong thing ("truncated",
// "header size", "checksum"). The version must be read and refused before any of them.
TEST(HsdfFile, NewerVersionIsRefusedAsNewerBeforeAnyOtherCheck) {
  const Bytes b = serialize(sphereContents());
  Bytes newer = b;
  put32(newer, 8, kHsdfVersion + 1);
  put32(newer, 12, 128);  // a longer header, as a later version might have
  const std::string whole = loadError(newer);
  EXPECT_TRUE(contains(whole, "unsupported version " + std::to_string(kHsdfVersion + 1) + ": the file is newer than this reader"))
      << whole;
  // Only the magic and the version: shorter than a version-1 header, still "newer", not "truncated".
  const Bytes headerOnly(newer.begin(), newer.begin() + 12);
  EXPECT_TRUE(contains(loadError(headerOnly), "newer than this reader")) << loadError(headerOnly);
  // Version 0 never existed: refused, but not called newer.
  Bytes zero = b;
  put32(zero, 8, 0);
  EXPECT_FALSE(contains(loadError(zero), "newer")) << loadError(zero);
  EXPECT_TRUE(contains(loadError(zero), "unsupported version 0")) << loadError(zero);
}

// Tricky: the header is checked field by field; each bad field is named.
TEST(HsdfFile, BadHeaderFieldsAreNamed) {
  const Bytes b = serialize(sphereContents());
  auto edited = [&](std::size_t at, std::uint32_t value) {
    Bytes copy = b;
    put32(copy, at, value);
    refreshChecksum(copy);
    return loadError(copy);
  };
  Bytes magic = b;
  magic[3] = 'G';
  EXPECT_TRUE(contains(loadError(magic), "not an .hsdf file"));
  EXPECT_TRUE(contains(edited(8, 2), "unsupported version 2"));
  EXPECT_TRUE(contains(edited(8, 0), "unsupported version 0"));
  EXPECT_TRUE(contains(edited(12, 64), "header size 64"));
  EXPECT_TRUE(contains(edited(16, 1), "resolution 1 outside"));
  EXPECT_TRUE(contains(edited(20, 7), "unknown scalar type 7"));
  EXPECT_TRUE(contains(edited(24, 8 | 3), "unknown flags 0xb"));
  // Bit 2 is the material section's (hsdf_materials_test.cpp): set on a file without one.
  EXPECT_TRUE(contains(edited(24, 4 | 3), "ends before its material section"));
  EXPECT_TRUE(contains(edited(24, 0), "no payload"));
  EXPECT_TRUE(contains(edited(28, 1), "reserved"));
  Bytes spacing = b;
  put64(spacing, 32, std::bit_cast<std::uint64_t>(-1.0));
  refreshChecksum(spacing);
  EXPECT_TRUE(contains(loadError(spacing), "spacing")) << loadError(spacing);
}

// Tricky: a single flipped bit anywhere (header, payload, checksum itself) must be caught.
TEST(HsdfFile, CorruptedBytesFailTheChecksum) {
  const Bytes b = serialize(sphereContents());
  for (std::size_t at : {std::size_t(33), std::size_t(200), b.size() / 2, b.size() - 9, b.size() - 1}) {
    Bytes corrupted = b;
    corrupted[at] ^= 0x10;
    const std::string error = loadError(corrupted);
    EXPECT_TRUE(contains(error, "checksum mismatch") || contains(error, "spacing")) << at << ": " << error;
  }
  Bytes payloadBit = b;
  payloadBit[b.size() / 2] ^= 1;
  EXPECT_TRUE(contains(loadError(payloadBit), "checksum mismatch"));
}

// Tricky: with a valid checksum (a buggy writer, not a damaged disk), values are still checked:
// NaN/inf scalars, cell coordinates outside the grid, unknown classes, unordered or duplicated
// records, and cells that contradict the dense field.
TEST(HsdfFile, InvalidValuesWithValidChecksumAreRefused) {
  const HsdfContents contents = sphereContents();
  const Bytes b = serialize(contents);
  const std::size_t cellsAt = 96 + 512 * 16;
  auto edited = [&](auto edit) {
    Bytes copy = b;
    edit(copy);
    refreshChecksum(copy);
    return loadError(copy);
  };
  EXPECT_TRUE(contains(edited([](Bytes& c) { put32(c, 96 + 16 * 9 + 4, 0x7fc00000u); }),
                       "dense sample 9 (1, 1, 0) is not finite"));
  EXPECT_TRUE(contains(edited([&](Bytes& c) { put32(c, cellsAt + 8 + 4, 0x7f800000u); }),
                       "cell record 0 has a value that is not finite"));
  EXPECT_TRUE(contains(edited([&](Bytes& c) { c[cellsAt] = 7; c[cellsAt + 1] = 0; }), "outside the 7^3 cells"));
  EXPECT_TRUE(contains(edited([&](Bytes& c) { c[cellsAt + 6] = 0; }), "has class 0"));
  EXPECT_TRUE(contains(edited([&](Bytes& c) {
                         std::memcpy(&c[cellsAt + 136], &c[cellsAt], 136);  // record 1 := record 0
                       }),
                       "cell record 1"));
  const std::string mismatch = edited([&](Bytes& c) { put32(c, cellsAt + 8, std::bit_cast<std::uint32_t>(123.0f)); });
  EXPECT_TRUE(contains(mismatch, "differs from the dense field")) << mismatch;
}

// Tricky: the writer refuses what the reader would refuse, instead of writing a file no one can
// load: no payload, values that overflow fp16, NaN, cells out of order or on another grid.
TEST(HsdfFile, SerializeRefusesInvalidContents) {
  HsdfContents empty = sphereContents();
  empty.dense.reset();
  empty.cells.reset();
  EXPECT_TRUE(contains(serializeHsdf(empty).error().message, "nothing to save"));

  HsdfContents big = sphereContents(HsdfScalarType::Float16, true, false);
  big.dense->samples[5].f = 1e6f;
  EXPECT_TRUE(contains(serializeHsdf(big).error().message, "does not fit fp16"));

  HsdfContents nan = sphereContents(HsdfScalarType::Float32, true, false);
  nan.dense->samples[3].fy = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(contains(serializeHsdf(nan).error().message, "sample 3"));

  HsdfContents unordered = sphereContents(HsdfScalarType::Float32, false, true);
  std::swap(unordered.cells->records[0], unordered.cells->records[1]);
  EXPECT_TRUE(contains(serializeHsdf(unordered).error().message, "strictly increasing"));

  HsdfContents moved = sphereContents();
  moved.dense->grid.spacing *= 2.0;
  EXPECT_TRUE(contains(serializeHsdf(moved).error().message, "different grid"));
}

// Tricky: fp16 has a fixed absolute step (2^-24) below 2^-14, so on a fine grid the values within
// a cell of the surface round to a few steps, yet every other check of the file would pass: only
// re-deriving the cells from the stored dense field shows the damage. The spacing here is 1.3e-4
// (above the 2^-13 limit, accepted: the stored cells are those of the stored field) and 1.3e-5
// (refused naming fp16 and the spacing; fp32 stores it fine). The reader refuses what the writer
// refuses (an fp16 file whose spacing was edited below the limit), so that the format stays
// canonical: every file that loads can be written back.
TEST(HsdfFile, Fp16RefusesGridsTooFineForItsPrecision) {
  const HsdfContents coarse = sphereContents(HsdfScalarType::Float16, true, true, 4e-4);
  ASSERT_GE(coarse.grid.spacing, 1.0 / 8192.0);
  auto loaded = loadHsdfFromMemory(serialize(coarse));
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  const CellStream rederived = extractCells(*loaded->dense, classifyCells(*loaded->dense).value()).value();
  ASSERT_EQ(rederived.records.size(), loaded->cells->records.size());
  for (std::size_t r = 0; r < rederived.records.size(); ++r)
    EXPECT_EQ(rederived.records[r].cellClass, loaded->cells->records[r].cellClass) << "record " << r;

  const HsdfContents fine = sphereContents(HsdfScalarType::Float16, true, true, 4e-5);
  auto refused = serializeHsdf(fine);
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(contains(refused.error().message, "fp16 needs a grid spacing of at least 2^-13")) << refused.error().message;
  EXPECT_TRUE(serializeHsdf(sphereContents(HsdfScalarType::Float32, true, true, 4e-5)).ok());

  Bytes edited = serialize(coarse);
  put64(edited, 32, std::bit_cast<std::uint64_t>(1e-5));
  refreshChecksum(edited);
  EXPECT_TRUE(contains(loadError(edited), "fp16 needs a grid spacing of at least 2^-13")) << loadError(edited);
}

// Tricky: the path travels into every error, and save/load go through real files.
TEST(HsdfFile, SaveAndLoadThroughFiles) {
  const hsdftest::ScopedTempPath file("hsdf_file_test_sphere.hsdf");  // its own: tests run side by side
  const std::filesystem::path& path = file.path();
  ASSERT_TRUE(saveHsdf(path, sphereContents(HsdfScalarType::Float16)).ok());
  auto loaded = loadHsdf(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_TRUE(loaded->dense && loaded->cells);
  std::filesystem::remove(path);
  auto missing = loadHsdf(path);
  ASSERT_FALSE(missing.ok());
  EXPECT_TRUE(contains(missing.error().message, path.string()));
}

}  // namespace
}  // namespace hsdf
