// Writing .hsdf files (layout: docs/hsdf-format.md, io/hsdf_layout.h).
#include <cmath>

#include <fmt/format.h>

#include "engine/core/files.h"
#include "hermite_sdf/core/hsdf_file.h"
#include "io/hsdf_contents.h"
#include "io/hsdf_layout.h"

namespace hsdf {
namespace {

bool hasMaterials(const HsdfContentsView& contents) { return contents.palette && !contents.palette->empty(); }

// With a palette, every payload carries its slots (and they lie within it); without one, none does.
engine::Status checkMaterials(const HsdfContentsView& contents) {
  static const std::vector<SdfMaterial> kNone;
  const std::vector<SdfMaterial>& palette = hasMaterials(contents) ? *contents.palette : kNone;
  if (contents.dense) {
    if (!palette.empty() && contents.dense->materials.size() != contents.dense->samples.size())
      return engine::makeError(fmt::format("the dense field has {} material slots for {} samples",
                                           contents.dense->materials.size(), contents.dense->samples.size()));
    ENGINE_TRY(checkMaterialSlots(palette, contents.dense->materials, "the dense field"));
  }
  if (contents.cells) {
    if (!palette.empty() && contents.cells->materials.size() != contents.cells->records.size())
      return engine::makeError(fmt::format("the cell stream has {} material slot entries for {} records",
                                           contents.cells->materials.size(), contents.cells->records.size()));
    const auto& slots = contents.cells->materials;
    ENGINE_TRY(checkMaterialSlots(palette, {slots.empty() ? nullptr : slots.front().data(), slots.size() * 8},
                                  "the cell stream"));
  }
  return {};
}

engine::Status checkContents(const HsdfContentsView& contents) {
  ENGINE_TRY(checkStorable(contents.grid, contents.scalarType));
  if (!contents.dense && !contents.cells)
    return engine::makeError("nothing to save: the contents hold neither a dense field nor a cell stream");
  if (contents.dense) {
    if (!io::sameGrid(contents.dense->grid, contents.grid))
      return engine::makeError("the dense field lies on a different grid than the file's");
    if (contents.dense->samples.size() != contents.grid.sampleCount())
      return engine::makeError(fmt::format("the dense field has {} samples, its grid needs {}",
                                           contents.dense->samples.size(), contents.grid.sampleCount()));
  }
  if (contents.cells) {
    if (!io::sameGrid(contents.cells->grid, contents.grid))
      return engine::makeError("the cell stream lies on a different grid than the file's");
    ENGINE_TRY(io::checkCellRecords(*contents.cells, contents.grid.resolution));
    if (contents.dense) ENGINE_TRY(io::checkCellsMatchField(*contents.cells, *contents.dense));
  }
  return checkMaterials(contents);
}

// Appends one scalar; false if it is not finite or (fp16) does not fit binary16.
bool writeScalar(io::ByteWriter& out, HsdfScalarType type, float value) {
  if (!std::isfinite(value)) return false;
  if (type == HsdfScalarType::Float32) {
    out.f32(value);
    return true;
  }
  const std::uint16_t half = floatToHalf(value);
  out.u16(half);
  return (half & 0x7c00u) != 0x7c00u;  // exponent all ones: overflowed to infinity
}

bool writeSample(io::ByteWriter& out, HsdfScalarType type, const HermiteSample& s) {
  bool ok = writeScalar(out, type, s.f);
  ok = writeScalar(out, type, s.fx) && ok;
  ok = writeScalar(out, type, s.fy) && ok;
  return writeScalar(out, type, s.fz) && ok;
}

std::uint64_t payloadBytes(const HsdfContentsView& contents) {
  const std::uint64_t dense = contents.dense ? contents.dense->samples.size() : 0;
  const std::uint64_t cells = contents.cells ? contents.cells->records.size() : 0;
  const std::uint64_t materials =
      hasMaterials(contents) ? io::materialSectionBytes(contents.palette->size(), dense, cells) : 0;
  return dense * io::denseSampleBytes(contents.scalarType) + cells * io::cellRecordBytes(contents.scalarType) + materials;
}

void writeHeader(io::ByteWriter& out, const HsdfContentsView& contents) {
  out.raw(io::kMagic);
  out.u32(kHsdfVersion);
  out.u32(std::uint32_t(kHsdfHeaderBytes));
  out.u32(std::uint32_t(contents.grid.resolution));
  out.u32(std::uint32_t(contents.scalarType));
  out.u32((contents.dense ? io::kFlagDense : 0u) | (contents.cells ? io::kFlagCells : 0u) |
          (hasMaterials(contents) ? io::kFlagMaterials : 0u));
  out.u32(0);  // reserved
  out.f64(contents.grid.spacing);
  out.f64(contents.grid.origin.x);
  out.f64(contents.grid.origin.y);
  out.f64(contents.grid.origin.z);
  out.u64(contents.dense ? contents.dense->samples.size() : 0);
  out.u64(contents.cells ? contents.cells->records.size() : 0);
  out.u64(payloadBytes(contents));
  out.u64(0);  // reserved
}

engine::Status writeDense(io::ByteWriter& out, HsdfScalarType type, const HermiteField& field) {
  for (std::size_t s = 0; s < field.samples.size(); ++s) {
    if (!writeSample(out, type, field.samples[s]))
      return engine::makeError(fmt::format("dense field {} has a value that is not finite{}",
                                           io::describeSample(field.grid, s),
                                           type == HsdfScalarType::Float16 ? " or does not fit fp16" : ""));
  }
  return {};
}

engine::Status writeCells(io::ByteWriter& out, HsdfScalarType type, const CellStream& cells) {
  for (std::size_t r = 0; r < cells.records.size(); ++r) {
    const CellRecord& record = cells.records[r];
    out.u16(record.x);
    out.u16(record.y);
    out.u16(record.z);
    out.u16(record.cellClass);
    bool ok = true;
    for (const HermiteSample& corner : record.corners) ok = writeSample(out, type, corner) && ok;
    if (!ok)
      return engine::makeError(fmt::format("cell record {} has a value that is not finite{}", r,
                                           type == HsdfScalarType::Float16 ? " or does not fit fp16" : ""));
  }
  return {};
}

// The material section (docs/hsdf-format.md, "Materials"), after the cells: palette, then the slots.
void writeMaterials(io::ByteWriter& out, const HsdfContentsView& contents) {
  out.u32(std::uint32_t(contents.palette->size()));
  out.u32(0);  // reserved
  for (const SdfMaterial& m : *contents.palette) {
    for (int c = 0; c < 4; ++c) out.f32(m.baseColor[c]);
    out.f32(m.roughness);
    out.f32(m.metallic);
  }
  if (contents.dense) out.raw(contents.dense->materials);
  if (contents.cells)
    for (const CellMaterialSlots& slots : contents.cells->materials) out.raw(slots);
}

}  // namespace

engine::Status checkStorable(const GridSpec& grid, HsdfScalarType type) {
  ENGINE_TRY(validateGrid(grid));
  if (type != HsdfScalarType::Float32 && type != HsdfScalarType::Float16)
    return engine::makeError(fmt::format("unknown scalar type {}", std::uint32_t(type)));
  if (type == HsdfScalarType::Float16 && grid.spacing < kMinFp16Spacing)
    return engine::makeError(fmt::format("fp16 needs a grid spacing of at least 2^-13 ({:g}), this grid's is {:g}: "
                                         "values near the surface would lose their precision (store fp32, or scale "
                                         "the shape up)",
                                         kMinFp16Spacing, grid.spacing));
  return {};
}

std::uint64_t hsdfChecksum(std::span<const std::uint8_t> bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const std::uint8_t b : bytes) {
    hash ^= b;
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

engine::Expected<std::vector<std::uint8_t>> serializeHsdf(const HsdfContents& contents) {
  return serializeHsdf(HsdfContentsView{contents.grid, contents.scalarType, contents.dense ? &*contents.dense : nullptr,
                                        contents.cells ? &*contents.cells : nullptr, &contents.palette});
}

engine::Expected<std::vector<std::uint8_t>> serializeHsdf(const HsdfContentsView& contents) {
  if (auto status = checkContents(contents); !status) return status.error().withContext("cannot save .hsdf");
  io::ByteWriter out(kHsdfHeaderBytes + std::size_t(payloadBytes(contents)) + kHsdfTrailerBytes);
  writeHeader(out, contents);
  if (contents.dense) {
    if (auto status = writeDense(out, contents.scalarType, *contents.dense); !status)
      return status.error().withContext("cannot save .hsdf");
  }
  if (contents.cells) {
    if (auto status = writeCells(out, contents.scalarType, *contents.cells); !status)
      return status.error().withContext("cannot save .hsdf");
  }
  if (hasMaterials(contents)) writeMaterials(out, contents);
  out.u64(hsdfChecksum(out.bytes()));
  return std::move(out.bytes());
}

engine::Status saveHsdf(const std::filesystem::path& path, const HsdfContents& contents) {
  auto bytes = serializeHsdf(contents);
  if (!bytes) return bytes.error().withContext(path.string());
  return engine::writeBinaryFile(path, *bytes);
}

}  // namespace hsdf
