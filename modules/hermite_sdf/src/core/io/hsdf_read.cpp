// Reading .hsdf files: validate sizes, then the checksum, then every value (docs/hsdf-format.md).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "engine/core/files.h"
#include "hermite_sdf/core/hsdf_file.h"
#include "io/hsdf_contents.h"
#include "io/hsdf_layout.h"

namespace hsdf {
namespace {

struct Header {
  std::uint32_t version = 0;
  std::uint32_t headerBytes = 0;
  std::uint32_t resolution = 0;
  std::uint32_t scalarType = 0;
  std::uint32_t flags = 0;
  std::uint32_t reserved0 = 0;
  double spacing = 0.0;
  glm::dvec3 origin{0.0};
  std::uint64_t denseSamples = 0;
  std::uint64_t cellCount = 0;
  std::uint64_t payloadBytes = 0;
  std::uint64_t reserved1 = 0;
};

Header readHeader(const io::ByteReader& in) {
  namespace at = io::offset;
  Header h;
  h.version = in.u32(at::kVersion);
  h.headerBytes = in.u32(at::kHeaderBytes);
  h.resolution = in.u32(at::kResolution);
  h.scalarType = in.u32(at::kScalarType);
  h.flags = in.u32(at::kFlags);
  h.reserved0 = in.u32(at::kReserved0);
  h.spacing = in.f64(at::kSpacing);
  h.origin = {in.f64(at::kOrigin), in.f64(at::kOrigin + 8), in.f64(at::kOrigin + 16)};
  h.denseSamples = in.u64(at::kDenseSamples);
  h.cellCount = in.u64(at::kCellCount);
  h.payloadBytes = in.u64(at::kPayloadBytes);
  h.reserved1 = in.u64(at::kReserved1);
  return h;
}

// The version is checked right after the magic, before any size: a later version may have a
// different header or layout, and its reader's user must learn "newer version", not "truncated".
engine::Status checkVersion(std::uint32_t version) {
  if (version > kHsdfVersion)
    return engine::makeError(fmt::format("unsupported version {}: the file is newer than this reader, which reads "
                                         "version {} (update hermite_sdf or re-bake the file)",
                                         version, kHsdfVersion));
  if (version != kHsdfVersion)
    return engine::makeError(fmt::format("unsupported version {} (this reader reads version {})", version, kHsdfVersion));
  return {};
}

engine::Status checkIdentity(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < io::kMagic.size() || !std::equal(io::kMagic.begin(), io::kMagic.end(), bytes.begin()))
    return engine::makeError("not an .hsdf file (the first 8 bytes are not the HSDF magic)");
  if (bytes.size() >= io::offset::kVersion + 4) ENGINE_TRY(checkVersion(io::ByteReader(bytes).u32(io::offset::kVersion)));
  if (bytes.size() < kHsdfHeaderBytes + kHsdfTrailerBytes)
    return engine::makeError(fmt::format("truncated: the file has {} bytes, fewer than the {} of header and checksum",
                                         bytes.size(), kHsdfHeaderBytes + kHsdfTrailerBytes));
  return {};
}

engine::Status checkHeaderFields(const Header& h) {
  ENGINE_TRY(checkVersion(h.version));
  if (h.headerBytes != kHsdfHeaderBytes)
    return engine::makeError(fmt::format("header size {} is not {}", h.headerBytes, kHsdfHeaderBytes));
  if (h.reserved0 != 0 || h.reserved1 != 0) return engine::makeError("reserved header fields are not zero");
  if (h.scalarType > std::uint32_t(HsdfScalarType::Float16))
    return engine::makeError(fmt::format("unknown scalar type {} (0: fp32, 1: fp16)", h.scalarType));
  if ((h.flags & ~io::kKnownFlags) != 0) return engine::makeError(fmt::format("unknown flags 0x{:x}", h.flags));
  if ((h.flags & (io::kFlagDense | io::kFlagCells)) == 0)
    return engine::makeError("no payload: neither the dense nor the cells flag is set");
  if (h.resolution < 2 || h.resolution > std::uint32_t(kMaxResolution))
    return engine::makeError(fmt::format("resolution {} outside 2..{}", h.resolution, kMaxResolution));
  return checkStorable(GridSpec{int(h.resolution), h.origin, h.spacing}, HsdfScalarType(h.scalarType));
}

// The palette size of the material section (0 without the materials flag), which sizes the rest of
// the section: read where the dense field and the cells end (`values` bytes after the header),
// once the file is known to reach that far.
engine::Expected<std::uint64_t> readPaletteSize(const Header& h, std::uint64_t values, std::size_t fileSize,
                                                std::span<const std::uint8_t> bytes) {
  if (!(h.flags & io::kFlagMaterials)) return std::uint64_t(0);
  const std::uint64_t at = kHsdfHeaderBytes + values;
  if (values > fileSize || fileSize < at + io::kMaterialsHeaderBytes + kHsdfTrailerBytes)
    return engine::makeError(fmt::format("truncated: the materials flag is set but the file ends before its material "
                                         "section ({} bytes, the section starts at byte {})",
                                         fileSize, at));
  const std::uint32_t paletteSize = io::ByteReader(bytes).u32(std::size_t(at));
  if (paletteSize < 2 || paletteSize > kMaxMaterialSlots)
    return engine::makeError(fmt::format("material section: a palette of {} materials (a multi-material file has 2..{})",
                                         paletteSize, kMaxMaterialSlots));
  return std::uint64_t(paletteSize);
}

// Counts against the resolution, the payload size against the counts and the file size, the
// decoded size against the budget: after this every read is in bounds and every allocation small.
engine::Status checkSizes(const Header& h, std::size_t fileSize, std::span<const std::uint8_t> bytes,
                          const HsdfLoadOptions& options) {
  const std::uint64_t k = h.resolution;
  const std::uint64_t samples = k * k * k;
  const std::uint64_t cells = (k - 1) * (k - 1) * (k - 1);
  const bool dense = (h.flags & io::kFlagDense) != 0;
  const bool hasCells = (h.flags & io::kFlagCells) != 0;
  if (h.denseSamples != (dense ? samples : 0))
    return engine::makeError(fmt::format("dense sample count {} does not match {} (resolution {}, dense flag {})",
                                         h.denseSamples, dense ? samples : 0, k, dense ? "set" : "clear"));
  if (hasCells ? h.cellCount > cells : h.cellCount != 0)
    return engine::makeError(fmt::format("cell count {} is impossible for resolution {} (at most {}, 0 without the "
                                         "cells flag)",
                                         h.cellCount, k, hasCells ? cells : 0));
  const HsdfScalarType type = HsdfScalarType(h.scalarType);
  const std::uint64_t values = h.denseSamples * io::denseSampleBytes(type) + h.cellCount * io::cellRecordBytes(type);
  ENGINE_TRY_ASSIGN(const std::uint64_t paletteSize, readPaletteSize(h, values, fileSize, bytes));
  const std::uint64_t materials =
      (h.flags & io::kFlagMaterials) ? io::materialSectionBytes(paletteSize, h.denseSamples, h.cellCount) : 0;
  const std::uint64_t payload = values + materials;
  if (h.payloadBytes != payload)
    return engine::makeError(fmt::format("payload size {} does not match the counts, which need {}", h.payloadBytes, payload));
  const std::uint64_t expected = kHsdfHeaderBytes + payload + kHsdfTrailerBytes;
  if (fileSize < expected)
    return engine::makeError(fmt::format("truncated: the file has {} bytes, its header announces {}", fileSize, expected));
  if (fileSize > expected)
    return engine::makeError(fmt::format("{} unexpected bytes after the checksum", fileSize - expected));
  const std::uint64_t decoded = h.denseSamples * sizeof(HermiteSample) + h.cellCount * sizeof(CellRecord) + materials;
  if (decoded > options.memoryBudgetBytes)
    return engine::makeError(fmt::format("the contents need {} bytes in memory, over the budget of {}", decoded,
                                         options.memoryBudgetBytes));
  return {};
}

engine::Status checkChecksum(std::span<const std::uint8_t> bytes) {
  const std::size_t body = bytes.size() - kHsdfTrailerBytes;
  const std::uint64_t stored = io::ByteReader(bytes).u64(body);
  const std::uint64_t computed = hsdfChecksum(bytes.first(body));
  if (stored != computed)
    return engine::makeError(fmt::format("checksum mismatch (stored 0x{:016x}, computed 0x{:016x}): the file is corrupted",
                                         stored, computed));
  return {};
}

// Reads `count` samples starting at byte `at`; false if any scalar is not finite.
bool readSamples(const io::ByteReader& in, std::size_t at, HsdfScalarType type, HermiteSample* out, std::size_t count) {
  const std::size_t step = io::scalarBytes(type);
  bool finite = true;
  for (std::size_t s = 0; s < count; ++s) {
    float v[4];
    for (int c = 0; c < 4; ++c) {
      v[c] = type == HsdfScalarType::Float32 ? in.f32(at) : halfToFloat(in.u16(at));
      finite = finite && std::isfinite(v[c]);
      at += step;
    }
    out[s] = {v[0], v[1], v[2], v[3]};
  }
  return finite;
}

engine::Expected<HermiteField> readDense(const io::ByteReader& in, const GridSpec& grid, HsdfScalarType type) {
  HermiteField field;
  field.grid = grid;
  field.samples.resize(grid.sampleCount());
  const std::size_t step = std::size_t(io::denseSampleBytes(type));
  for (std::size_t s = 0; s < field.samples.size(); ++s) {
    if (!readSamples(in, kHsdfHeaderBytes + s * step, type, &field.samples[s], 1))
      return engine::makeError(fmt::format("dense {} is not finite (NaN or infinity)", io::describeSample(grid, s)));
  }
  return field;
}

engine::Expected<CellStream> readCells(const io::ByteReader& in, std::size_t at, std::uint64_t count,
                                       const GridSpec& grid, HsdfScalarType type) {
  CellStream stream;
  stream.grid = grid;
  stream.records.resize(std::size_t(count));
  const std::size_t step = std::size_t(io::cellRecordBytes(type));
  for (std::size_t r = 0; r < stream.records.size(); ++r, at += step) {
    CellRecord& record = stream.records[r];
    record.x = in.u16(at);
    record.y = in.u16(at + 2);
    record.z = in.u16(at + 4);
    record.cellClass = in.u16(at + 6);
    if (!readSamples(in, at + 8, type, record.corners.data(), record.corners.size()))
      return engine::makeError(fmt::format("cell record {} has a value that is not finite (NaN or infinity)", r));
  }
  ENGINE_TRY(io::checkCellRecords(stream, grid.resolution));
  return stream;
}

// Every corner slot of every record equals the dense field's slot of that sample.
engine::Status checkCellSlotsMatchField(const CellStream& cells, const HermiteField& field) {
  for (std::size_t r = 0; r < cells.records.size(); ++r) {
    const CellRecord& record = cells.records[r];
    for (int c = 0; c < 8; ++c) {
      const std::size_t s = field.grid.sampleIndex(record.x + (c & 1), record.y + ((c >> 1) & 1), record.z + ((c >> 2) & 1));
      if (cells.materials[r][std::size_t(c)] != field.materials[s])
        return engine::makeError(fmt::format("cell record {} ({}, {}, {}) corner {} has material slot {}, the dense "
                                             "field's sample there {}",
                                             r, record.x, record.y, record.z, c, int(cells.materials[r][std::size_t(c)]),
                                             int(field.materials[s])));
    }
  }
  return {};
}

// The palette and the slots (docs/hsdf-format.md, "Materials") into `contents`, whose payloads are
// read: every value finite, every slot within the palette, each cell's corner slots those of the
// dense samples there when both are present.
engine::Status readMaterials(const io::ByteReader& in, std::size_t at, HsdfContents& contents) {
  const std::uint32_t paletteSize = in.u32(at);
  if (in.u32(at + 4) != 0) return engine::makeError("its reserved field is not zero");
  at += std::size_t(io::kMaterialsHeaderBytes);
  for (std::uint32_t e = 0; e < paletteSize; ++e, at += std::size_t(io::kPaletteEntryBytes)) {
    SdfMaterial m;
    for (int c = 0; c < 4; ++c) m.baseColor[c] = in.f32(at + 4 * std::size_t(c));
    m.roughness = in.f32(at + 16);
    m.metallic = in.f32(at + 20);
    contents.palette.push_back(m);
  }
  if (contents.dense) {
    contents.dense->materials.resize(contents.dense->samples.size());
    for (std::uint8_t& slot : contents.dense->materials) slot = in.u8(at++);
    ENGINE_TRY(checkMaterialSlots(contents.palette, contents.dense->materials, "dense field"));
  }
  if (contents.cells) {
    contents.cells->materials.resize(contents.cells->records.size());
    for (CellMaterialSlots& slots : contents.cells->materials)
      for (MaterialSlot& slot : slots) slot = in.u8(at++);
    const auto& cellSlots = contents.cells->materials;
    ENGINE_TRY(checkMaterialSlots(contents.palette, {cellSlots.empty() ? nullptr : cellSlots.front().data(), cellSlots.size() * 8},
                                  "cell stream"));
    if (contents.dense) ENGINE_TRY(checkCellSlotsMatchField(*contents.cells, *contents.dense));
  }
  return {};
}

engine::Expected<HsdfContents> readContents(std::span<const std::uint8_t> bytes, const HsdfLoadOptions& options) {
  ENGINE_TRY(checkIdentity(bytes));
  const io::ByteReader in(bytes);
  const Header header = readHeader(in);
  ENGINE_TRY(checkHeaderFields(header));
  ENGINE_TRY(checkSizes(header, bytes.size(), bytes, options));
  ENGINE_TRY(checkChecksum(bytes));
  HsdfContents contents;
  contents.grid = GridSpec{int(header.resolution), header.origin, header.spacing};
  contents.scalarType = HsdfScalarType(header.scalarType);
  std::size_t cellsAt = kHsdfHeaderBytes;
  if (header.flags & io::kFlagDense) {
    ENGINE_TRY_ASSIGN(contents.dense, readDense(in, contents.grid, contents.scalarType));
    cellsAt += std::size_t(header.denseSamples * io::denseSampleBytes(contents.scalarType));
  }
  if (header.flags & io::kFlagCells) {
    ENGINE_TRY_ASSIGN(contents.cells, readCells(in, cellsAt, header.cellCount, contents.grid, contents.scalarType));
    if (contents.dense) ENGINE_TRY(io::checkCellsMatchField(*contents.cells, *contents.dense));
  }
  if (header.flags & io::kFlagMaterials) {
    const std::size_t materialsAt =
        cellsAt + std::size_t(header.cellCount * io::cellRecordBytes(contents.scalarType));
    ENGINE_TRY(readMaterials(in, materialsAt, contents).withContext("material section"));
  }
  return contents;
}

}  // namespace

engine::Expected<HsdfContents> loadHsdfFromMemory(std::span<const std::uint8_t> bytes, const HsdfLoadOptions& options) {
  return readContents(bytes, options).withContext("invalid .hsdf");
}

engine::Expected<HsdfContents> loadHsdf(const std::filesystem::path& path, const HsdfLoadOptions& options) {
  // A payload is never larger on disk than in memory (fp32 records have the in-memory size, fp16
  // ones half), so a file beyond the budget plus framing cannot be valid: refused before reading.
  auto bytes = engine::readBinaryFile(path, options.memoryBudgetBytes + kHsdfHeaderBytes + kHsdfTrailerBytes);
  if (!bytes) return bytes.error();
  return loadHsdfFromMemory(*bytes, options).withContext(path.string());
}

bool startsWithHsdfMagic(std::span<const std::uint8_t> bytes) {
  return bytes.size() >= io::kMagic.size() && std::equal(io::kMagic.begin(), io::kMagic.end(), bytes.begin());
}

}  // namespace hsdf
