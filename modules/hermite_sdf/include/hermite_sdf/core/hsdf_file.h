#pragma once
// .hsdf files: a dense Hermite field and/or its sparse cell stream, versioned, little-endian,
// checksummed. The byte layout is specified in docs/hsdf-format.md (offsets, types, checksum with
// a test vector), precisely enough for other tools to read and write it.
//
// Loading validates everything before it trusts anything: sizes are checked against the file
// size and a memory budget before any allocation (no overflow, no huge allocation from a forged
// count), the checksum before any value is read, then every value (finite scalars, cell
// coordinates inside the grid, cells strictly increasing, cell corners equal to the dense field
// when both are present). Each failure is an error naming the problem.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "engine/core/expected.h"
#include "hermite_sdf/core/cells.h"
#include "hermite_sdf/core/field.h"
#include "hermite_sdf/core/materials.h"

namespace hsdf {

inline constexpr std::uint32_t kHsdfVersion = 1;
inline constexpr std::size_t kHsdfHeaderBytes = 96;
inline constexpr std::size_t kHsdfTrailerBytes = 8;

// How scalars (f, fx, fy, fz) are stored in the file. In memory they are always float; fp16 files
// round them to IEEE binary16 on save.
enum class HsdfScalarType : std::uint32_t { Float32 = 0, Float16 = 1 };

struct HsdfContents {
  GridSpec grid;
  HsdfScalarType scalarType = HsdfScalarType::Float32;
  std::optional<HermiteField> dense;  // on `grid`
  std::optional<CellStream> cells;    // on `grid`, records in increasing cell index order
  // A multi-material field (materials.h): the palette its slots index (dense->materials and
  // cells->materials, each present with its payload). Empty: one material (no material section).
  std::vector<SdfMaterial> palette;
};

// The same contents by reference, for saving payloads that live elsewhere (an asset's cells)
// without copying them: a K = 2048 cell stream is 1.8 GB.
struct HsdfContentsView {
  GridSpec grid;
  HsdfScalarType scalarType = HsdfScalarType::Float32;
  const HermiteField* dense = nullptr;  // on `grid`, or none
  const CellStream* cells = nullptr;    // on `grid`, records in increasing cell index order, or none
  const std::vector<SdfMaterial>* palette = nullptr;  // as HsdfContents::palette; null or empty: none
};

struct HsdfLoadOptions {
  // Largest decoded size accepted (payload as floats in memory); larger files are refused before
  // anything is allocated.
  std::uint64_t memoryBudgetBytes = std::uint64_t(4) << 30;
};

// Whether `bytes` start with the .hsdf magic: a tool given a baked file where it wants a mesh names
// the mix-up instead of failing to parse it as what it wanted.
bool startsWithHsdfMagic(std::span<const std::uint8_t> bytes);

// FNV-1a, 64 bit (offset basis 0xcbf29ce484222325, prime 0x100000001b3) over `bytes`: the file
// checksum, computed over everything before the trailer.
std::uint64_t hsdfChecksum(std::span<const std::uint8_t> bytes);

// Whether a field on `grid` can be stored with `type`: a valid grid, and for fp16 a spacing of at
// least 2^-13 (finer grids would lose the precision of the values near the surface, see
// docs/hsdf-format.md). The writer and the reader check it; a baker can check it before the work.
engine::Status checkStorable(const GridSpec& grid, HsdfScalarType type);

// The file image of `contents`. Errors: invalid grid, no payload, a payload on another grid or of
// the wrong size, cells out of range or out of order, non-finite values, values too large for fp16.
engine::Expected<std::vector<std::uint8_t>> serializeHsdf(const HsdfContents& contents);
engine::Expected<std::vector<std::uint8_t>> serializeHsdf(const HsdfContentsView& contents);
engine::Status saveHsdf(const std::filesystem::path& path, const HsdfContents& contents);

engine::Expected<HsdfContents> loadHsdfFromMemory(std::span<const std::uint8_t> bytes,
                                                  const HsdfLoadOptions& options = {});
// Errors are prefixed with the path.
engine::Expected<HsdfContents> loadHsdf(const std::filesystem::path& path, const HsdfLoadOptions& options = {});

}  // namespace hsdf
