// The cell feature's GPU copy of the drawn assets: records, runs, bricks and normal cones.
#include "hermite_sdf/render/cell_feature.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <unordered_map>
#include <unordered_set>

#include <imgui.h>

#include "engine/core/log.h"
#include "engine/ecs/registry.h"
#include "engine/gpu/allocate_or_refuse.h"
#include "engine/gpu/context.h"
#include "engine/gpu/vk_check.h"
#include "engine/render/gpu_scene.h"
#include "engine/scene/transform.h"
#include "hermite/hermite_host_device.h"
#include "cells/cell_bricks.h"
#include "render/brick_culler.h"
#include "render/cell_feature_internal.h"
#include "render/cell_history.h"
#include "cells/cell_rows.h"
#include "hermite_sdf/render/lod.h"
#include "hermite_sdf/core/normal_cone.h"

namespace hsdf {

const std::vector<shader::CellBrickGpu>& CellBuffers::Entry::bricks() const {
  static const std::vector<shader::CellBrickGpu> kNone;
  const CellDerived* derived = bricksUploaded ? matchingDerived(*asset) : nullptr;
  return derived && derived->bricksProblem.empty() ? derived->bricks.bricks : kNone;
}

namespace {

// The asset's derived data (the bake job made it), or null with a warning naming what the asset
// lacks: then its cells draw unculled and it draws nothing as bricks.
const CellDerived* derivedOrWarn(const SdfAsset& asset) {
  if (const CellDerived* derived = matchingDerived(asset)) return derived;
  engine::log::warn("hermite cells: '{}' has no normal cones or bricks (an asset made without make*Asset, or whose "
                    "records changed after): its cells are drawn unculled and it is not drawn as cell bricks",
                    asset.name);
  return nullptr;
}

// The asset's rows: its derived data's (made with it, off the render thread; an alias that lives as
// long as they do), or built now for an asset without.
std::shared_ptr<const CellRows> rowsOf(const std::shared_ptr<const SdfAsset>& asset, const CellDerived* derived) {
  if (derived) return {asset->derived, &derived->rows};
  return std::make_shared<const CellRows>(buildCellRows(asset->cells));
}

// The asset's runs of at most `maxLength` cells: its derived data's when they have that length,
// else built now (an asset without derived data, or a run length set other than the default: a
// tuning setting, whose change rebuilds every buffer anyway; not kept per length, which would hold
// the memory of every length tried for as long as the asset lives).
std::shared_ptr<const std::vector<shader::CellRunGpu>> runsOf(const std::shared_ptr<const SdfAsset>& asset,
                                                               const CellDerived* derived, std::uint32_t maxLength) {
  if (derived && derived->runLength == std::clamp(maxLength, 1u, 0xffffu)) return {asset->derived, &derived->runs};
  return std::make_shared<const std::vector<shader::CellRunGpu>>(buildCellRuns(asset->cells, maxLength));
}

// The asset's bricks and their cones, or none when it has none (a grid too large for brick
// coordinates: reported; its CellBricks objects draw nothing).
const CellDerived* bricksOf(const SdfAsset& asset, const CellDerived* derived) {
  if (derived && derived->bricksProblem.empty()) return derived;
  if (derived) engine::log::warn("hermite cells: '{}' cannot be drawn as cell bricks: {}", asset.name, derived->bricksProblem);
  return nullptr;
}

}  // namespace

// What this frame draws as cells, runs or bricks: the assets, and which need bricks or cell cones.
struct HermiteCellFeature::AssetDemand {
  std::vector<std::shared_ptr<const SdfAsset>> wanted;
  std::unordered_set<std::uint64_t> seen;
  std::unordered_set<std::uint64_t> asBricks;  // assets some entity draws as cell bricks
  bool missing = false;
  // The new assets wanted whose records the buffers hold already (uploadInParts: written over
  // earlier frames; then they are the only new ones), each at its first record: appended in place,
  // or copied by a rebuild like the kept assets. The other new assets wait.
  std::unordered_map<std::uint64_t, std::uint32_t> resident;
};

// The concatenation of the wanted assets' streams: the contents of the rebuilt buffers, or what is
// appended to the uploaded ones (then `base` is where it goes: the entries they hold). The
// per-record streams (fp32 and fp16 records, cell cones: 224 bytes a cell) and the runs are not
// copied here but written from their assets (and entries) straight into the staging memory
// (recordWriters, runAppend), or, for the records of the assets a rebuild keeps, copied on the GPU
// from the old buffers (recordCopies); the rest is small.
struct HermiteCellFeature::AssetUpload {
  // Records [first, first + count) of an asset (all of them by default), clipped to those it has.
  struct RecordSource {
    const SdfAsset* asset = nullptr;
    const CellDerived* derived = nullptr;  // its cell cones; null: cones that never cull
    std::size_t first = 0;
    std::size_t count = SIZE_MAX;
  };
  // An asset's runs (its entry's, which outlive the upload), written with their records at `firstRecord`.
  struct RunSource {
    const std::vector<shader::CellRunGpu>* runs = nullptr;
    std::uint32_t firstRecord = 0;
  };
  // An asset the old buffers hold, its records at `from` there and at `to` here (a rebuild).
  struct RecordCopy {
    std::uint32_t from = 0, to = 0, records = 0, halfRecords = 0;
  };
  StreamCounts base;
  std::vector<RecordSource> recordSources;  // in record order, before the copied records
  std::vector<RecordCopy> recordCopies;
  // A rebuild while an asset is written in parts (partial_): its records written so far, copied
  // after every entry's records, and the records of room made there for all of it, so that its
  // later parts go in place (it goes on, not from its first record again).
  RecordCopy carried;
  std::uint32_t carriedRoom = 0;
  std::uint32_t records = 0, halfRecords = 0;
  // The records (and their cones) were written in earlier frames, after `base` (a new asset
  // uploaded in parts: Settings::uploadBytesPerFrame): the other streams alone are appended.
  bool recordsResident = false;
  std::vector<RunSource> runSources;
  std::uint32_t runs = 0;  // of every run source
  std::vector<shader::CellBrickGpu> bricks;
  std::vector<std::uint32_t> brickCells;
  std::vector<shader::CellBrickCone> cones;
  std::vector<CellMaterialSlots> materialSlots;           // the multi-material assets' records only
  std::vector<shader::HermiteMaterialGpu> palette;        // their palettes

  // The bytes of the buffers made from these streams.
  VkDeviceSize bytes() const {
    return VkDeviceSize(records) * (sizeof(CellRecord) + sizeof(shader::CellBrickCone)) +
           VkDeviceSize(halfRecords) * sizeof(CellRecordHalf) + VkDeviceSize(runs) * sizeof(shader::CellRunGpu) +
           bricks.size() * sizeof(shader::CellBrickGpu) + brickCells.size() * sizeof(std::uint32_t) +
           cones.size() * sizeof(shader::CellBrickCone) + materialSlots.size() * sizeof(CellMaterialSlots) +
           palette.size() * sizeof(shader::HermiteMaterialGpu);
  }
  static VkDeviceSize bytesOf(const RecordCopy& c) {
    return VkDeviceSize(c.records) * (sizeof(CellRecord) + sizeof(shader::CellBrickCone)) +
           VkDeviceSize(c.halfRecords) * sizeof(CellRecordHalf);
  }
  // The per-record bytes the GPU copies from the old buffers (recordCopies, carried).
  VkDeviceSize copiedBytes() const {
    VkDeviceSize copied = bytesOf(carried);
    for (const RecordCopy& c : recordCopies) copied += bytesOf(c);
    return copied;
  }
  // The bytes this upload writes from the CPU: bytes() less the records written before or copied
  // (the carried part, of no entry yet, is not in bytes()).
  VkDeviceSize writtenBytes() const {
    return bytes() + bytesOf(carried) - copiedBytes() -
           (recordsResident ? VkDeviceSize(records) * HermiteCellFeature::kRecordUploadBytes : 0);
  }
  // The copies from the old buffers: the entries' and the carried part.
  std::vector<RecordCopy> allCopies() const {
    std::vector<RecordCopy> all = recordCopies;
    if (carried.records != 0) all.push_back(carried);
    return all;
  }
  // The entries of the buffers once these streams are in.
  StreamCounts end() const {
    return {base.records + records, base.runs + runs,
            base.bricks + std::uint32_t(bricks.size()), base.brickCells + std::uint32_t(brickCells.size()),
            base.materialSlots + std::uint32_t(materialSlots.size()), base.palette + std::uint32_t(palette.size())};
  }
};

const std::uint64_t HermiteCellFeature::kRecordUploadBytes =
    sizeof(CellRecord) + sizeof(CellRecordHalf) + sizeof(shader::CellBrickCone);

namespace {

// The records are vertex attributes in the prepass and read by address in the resolve pass; the
// runs are vertex attributes only.
constexpr VkBufferUsageFlags kAddressUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
constexpr VkBufferUsageFlags kVertexUsage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;

// An append of `items` (which outlive it) after the `used` bytes of `buffer`.
template <class T>
engine::gpu::BufferAppend appendOf(Buffer& buffer, VkDeviceSize used, const std::vector<T>& items,
                                   VkBufferUsageFlags usage, const char* name) {
  const std::span<const std::byte> bytes = std::as_bytes(std::span(items));
  return {&buffer, used, bytes.size(), engine::gpu::copyOf(bytes), usage, name};
}

// The entries of a stream of `size` entries that records [first, first + count) hold.
std::size_t clippedCount(std::size_t size, std::size_t first, std::size_t count) {
  return std::min(count, size - std::min(first, size));
}

// The GPU copies of the records carry their proxy box beside the class (CELL_PROXY_SHIFT); an asset
// without codes (made by hand) keeps the whole cells (code 0). Record by record through a local:
// `out` is staging memory, which may be write-combined (never read back).
// `first` and `count` pick the records written (a part of an upload spread over frames).
template <class Record>
std::byte* writeRecords(const std::vector<Record>& records, const std::vector<std::uint16_t>& codes, std::byte* out,
                        std::size_t first, std::size_t count) {
  count = clippedCount(records.size(), first, count);
  if (codes.size() != records.size()) {
    std::memcpy(out, records.data() + first, count * sizeof(Record));
    return out + count * sizeof(Record);
  }
  for (std::size_t i = first; i < first + count; ++i, out += sizeof(Record)) {
    Record record = records[i];
    record.cellClass = std::uint16_t(record.cellClass | (codes[i] << CELL_PROXY_SHIFT));
    std::memcpy(out, &record, sizeof(Record));
  }
  return out;
}

// The asset's cell cones (one per record, what the cell culling pass reads), or cones that never
// cull for an asset without them.
std::byte* writeCellCones(const SdfAsset& asset, const CellDerived* derived, std::byte* out, std::size_t first,
                          std::size_t count) {
  count = clippedCount(asset.cells.records.size(), first, count);
  if (derived) {
    std::memcpy(out, derived->cellCones.data() + first, count * sizeof(shader::CellBrickCone));
    return out + count * sizeof(shader::CellBrickCone);
  }
  const shader::CellBrickCone never = neverCullCone();
  for (std::size_t i = 0; i < count; ++i, out += sizeof(never)) std::memcpy(out, &never, sizeof(never));
  return out;
}

// The writers of the per-record streams (fp32 records, fp16 records, cell cones), from `sources`
// (which outlive them) straight into the staging memory.
template <class Source>
std::array<engine::gpu::BufferAppend::Writer, 3> recordWriters(std::span<const Source> sources) {
  return {
      [sources](std::span<std::byte> out) {
        std::byte* at = out.data();
        for (const Source& s : sources)
          at = writeRecords(s.asset->cells.records, s.asset->proxyBoxes, at, s.first, s.count);
      },
      [sources](std::span<std::byte> out) {
        std::byte* at = out.data();
        for (const Source& s : sources)
          at = writeRecords(s.asset->cellsHalf.records, s.asset->proxyBoxesHalf, at, s.first, s.count);
      },
      [sources](std::span<std::byte> out) {
        std::byte* at = out.data();
        for (const Source& s : sources) at = writeCellCones(*s.asset, s.derived, at, s.first, s.count);
      },
  };
}

// The appends of the per-record streams (fp32 and fp16 records, cell cones) of `sources`, written
// at record `at` of the buffers (the same index in each), each buffer made or grown with room for
// `reserve` records from there when that is more than the sources hold: the later parts of an
// asset written over several frames then go in place.
template <class Source>
std::vector<engine::gpu::BufferAppend> recordAppends(CellBuffers& b, std::span<const Source> sources, std::uint32_t at,
                                                     std::uint32_t reserve = 0) {
  std::size_t records = 0, halfRecords = 0;
  for (const Source& s : sources) {
    records += clippedCount(s.asset->cells.records.size(), s.first, s.count);
    halfRecords += clippedCount(s.asset->cellsHalf.records.size(), s.first, s.count);
  }
  const auto append = [&](Buffer& buffer, std::size_t size, std::size_t entries, engine::gpu::BufferAppend::Writer write,
                          VkBufferUsageFlags usage, const char* name) {
    engine::gpu::BufferAppend a{&buffer, VkDeviceSize(at) * size, VkDeviceSize(entries) * size, std::move(write), usage, name};
    a.reserve = VkDeviceSize(reserve) * size;
    return a;
  };
  auto [full, half, cellCones] = recordWriters(sources);
  std::vector<engine::gpu::BufferAppend> appends;
  appends.push_back(append(b.records[0], sizeof(CellRecord), records, std::move(full), kVertexUsage | kAddressUsage,
                           "hermite cells fp32"));
  appends.push_back(append(b.records[1], sizeof(CellRecordHalf), halfRecords, std::move(half),
                           kVertexUsage | kAddressUsage, "hermite cells fp16"));
  appends.push_back(append(b.cellCones, sizeof(shader::CellBrickCone), records, std::move(cellCones), kAddressUsage,
                           "hermite cell cones"));
  return appends;
}

static_assert(sizeof(CellMaterialSlots) == sizeof(shader::CellMaterialSlotsGpu), "materials.h and hermite_host_device.h");

// The append of the upload's runs after the `used` runs of the buffer: each source's runs written
// straight into the staging memory (run by run through a local: it may be write-combined), their
// first record made global.
template <class Upload>
engine::gpu::BufferAppend runAppend(CellBuffers& b, const Upload& u, std::uint32_t used) {
  const auto write = [sources = std::span(u.runSources)](std::span<std::byte> out) {
    std::byte* at = out.data();
    for (const auto& source : sources)
      for (shader::CellRunGpu run : *source.runs) {
        run.firstRecord += source.firstRecord;
        std::memcpy(at, &run, sizeof(run));
        at += sizeof(run);
      }
  };
  return {&b.runs, VkDeviceSize(used) * sizeof(shader::CellRunGpu), VkDeviceSize(u.runs) * sizeof(shader::CellRunGpu),
          write, kVertexUsage, "hermite cell runs"};
}

// The seven cell buffers as appends of the upload's streams after the `used` entries they hold,
// with each buffer's usage (records resident: no record source, none of theirs).
template <class Upload>
std::vector<engine::gpu::BufferAppend> cellStreamAppends(CellBuffers& b, const Upload& u, const StreamCounts& used) {
  constexpr VkBufferUsageFlags address = kAddressUsage, vertex = kVertexUsage;
  const auto entries = [](std::uint32_t count, std::size_t size) { return VkDeviceSize(count) * size; };
  // Copied records (a rebuild) go after the written ones: the buffers are made with room for them,
  // and for all of an asset written in parts whose first records are carried over.
  const std::uint32_t room = u.recordCopies.empty() && u.carriedRoom == 0 ? 0 : u.records + u.carriedRoom;
  std::vector<engine::gpu::BufferAppend> appends = recordAppends(b, std::span(u.recordSources), used.records, room);
  appends.push_back(runAppend(b, u, used.runs));
  appends.push_back(appendOf(b.bricks, entries(used.bricks, sizeof(shader::CellBrickGpu)), u.bricks, vertex | address,
                             "hermite cell bricks"));
  appends.push_back(appendOf(b.brickCells, entries(used.brickCells, sizeof(std::uint32_t)), u.brickCells, address,
                             "hermite cell brick cells"));
  appends.push_back(appendOf(b.brickCones, entries(used.bricks, sizeof(shader::CellBrickCone)), u.cones, address,
                             "hermite cell brick cones"));
  return appends;
}

// The cell buffers' appends, then the multi-material assets' corner slots and palettes (read by
// address in the resolve pass) only where there are some: an upload of assets of one material
// makes no material buffers, and costs what it did.
template <class Upload>  // HermiteCellFeature::AssetUpload, private to the feature
std::vector<engine::gpu::BufferAppend> streamAppends(CellBuffers& b, const Upload& u, const StreamCounts& used) {
  std::vector<engine::gpu::BufferAppend> appends = cellStreamAppends(b, u, used);
  constexpr VkBufferUsageFlags address = kAddressUsage;
  if (!u.materialSlots.empty())
    appends.push_back(appendOf(b.materialSlots, VkDeviceSize(used.materialSlots) * sizeof(CellMaterialSlots),
                               u.materialSlots, address, "hermite cell material slots"));
  if (!u.palette.empty())
    appends.push_back(appendOf(b.palette, VkDeviceSize(used.palette) * sizeof(shader::HermiteMaterialGpu), u.palette,
                               address, "hermite cell palettes"));
  return appends;
}

// Never an empty buffer (a zero-sized buffer is invalid): a buffer not made yet that gets no bytes
// (nor room for copied ones) gets padding no draw reaches, as large as any entry, overwritten by
// the first asset appended with bricks or cones (its `used` stays 0).
void padEmptyBuffers(std::span<engine::gpu::BufferAppend> appends) {
  static constexpr std::array<std::byte, 64> kPadding{};
  for (engine::gpu::BufferAppend& a : appends)
    if (a.bytes == 0 && a.reserve == 0 && !*a.buffer) {
      a.bytes = kPadding.size();
      a.write = engine::gpu::copyOf(kPadding);
    }
}

}  // namespace

// Uploads the assets drawn now when one is new, needs bricks, or the run length changed.
void HermiteCellFeature::syncAssets(const engine::render::FrameContext& frame) {
  settlePendingCopies(frame);
  forgetRefusalsThatMayFit();
  AssetDemand d = collectAssetDemand(frame);
  if (settings_.uploadBytesPerFrame != 0) {
    uploadInParts(frame, d);
  } else {  // every new asset comes whole, after the records the buffers hold
    partial_.reset();
    assetsWaiting_ = 0;
  }
  // Nothing uploaded yet (the first asset is being written in parts): no runs to be stale.
  const bool runsStale = !d.wanted.empty() && !buffers_->entries.empty() && buffers_->runLength != settings_.maxRunLength &&
                         settings_.maxRunLength != refusedRunLength_;  // the setting changed
  const bool drop = idleAssetsToDrop(frame);
  if (!d.missing && !runsStale && !drop) return;
  // A rebuild earlier in this frame copies records in this frame's commands, not submitted yet: an
  // append now (its own submission, which runs first) would copy the new buffers before they hold
  // them. The next frame uploads.
  if (pendingCopies_) return;

  // View regions call prepare() once per region: an asset an earlier region of this frame drew
  // stays (its draws are recorded already and the next frame draws it again), and so does one that
  // a later region drew last frame (a split screen's other side drawing the entity from another
  // asset: dropped here, that side would write it again, or draw nothing while it comes in parts).
  const auto keep = [&](std::uint64_t id) {
    if (auto entry = buffers_->entries.find(id); entry != buffers_->entries.end() && d.seen.insert(id).second)
      d.wanted.push_back(entry->second.asset);
  };
  for (const auto& [id, entry] : buffers_->entries)
    if (entry.lastFrame == frame.frameNumber) keep(id);
  drawnAssets_.forOtherRegions(keep);

  if (!runsStale && !drop && appendNewAssets(frame, d)) return;
  if (d.wanted.empty()) {  // no asset drawn any more (idleAssetsToDrop): every buffer goes, as at the start
    partial_.reset();
    frame.retire(std::move(buffers_));
    buffers_ = std::make_unique<CellBuffers>();
    return;
  }
  // Rebuild the concatenated buffers with the assets drawn now (assets no longer drawn are dropped).
  // The old buffers may be referenced by commands recorded earlier in this frame and by frames in
  // flight: they are retired below, and freed once this frame has completed.
  std::string failure;
  VkDeviceSize needed = 0;
  {
    CellBuffers rebuilt;
    AssetUpload u;
    // The assets written from the CPU first, then those the old buffers hold (copied on the GPU):
    // the kept ones and the new ones written in parts.
    const auto held = [&](const auto& asset) {
      return buffers_->entries.contains(asset->id) || d.resident.contains(asset->id);
    };
    for (const auto& asset : d.wanted)
      if (!held(asset)) appendAsset(rebuilt, u, asset, d);
    for (const auto& asset : d.wanted)
      if (held(asset)) appendAsset(rebuilt, u, asset, d);
    carryPartialUpload(u);
    rebuilt.used = u.end();
    if (const engine::Status created = engine::gpu::allocateOrRefuse([&] { createAssetBuffers(rebuilt, u); });
        !created) {
      failure = created.error().message;
      needed = u.bytes();  // at least (the staging copies come on top)
    }
    if (failure.empty()) return commitAssetBuffers(frame, std::move(rebuilt), u);
  }  // the buffers built so far are given back before the refusal notes the memory in use
  refuseNewAssets(frame, d.wanted, failure, needed);  // the old buffers stay: what was drawn is drawn
}

// Refusals whose upload may fit now (memory given back or the budget raised since) are forgotten:
// those assets, or that run length, are tried again (and reported again if refused). A refusal is
// otherwise kept, so that a full GPU is not asked every frame.
void HermiteCellFeature::forgetRefusalsThatMayFit() {
  const engine::gpu::Allocator& allocator = context_->allocator();
  std::erase_if(refused_, [&allocator](const auto& refusal) { return refusal.second.mayRetry(allocator); });
  if (runsRefusal_ && runsRefusal_->mayRetry(allocator)) {
    runsRefusal_.reset();
    refusedRunLength_ = 0;
  }
}

namespace {

// Whether an uploaded asset now drawn as bricks lacks its bricks.
template <class Demand>
bool bricksMissing(const Demand& d, const CellBuffers& buffers) {
  for (std::uint64_t id : d.asBricks)
    if (auto entry = buffers.entries.find(id); entry != buffers.entries.end() && !entry->second.bricksUploaded)
      return true;
  return false;
}

}  // namespace

// A budget per frame (Settings::uploadBytesPerFrame): new assets that fit it together, none begun
// in an earlier frame, are uploaded whole as without a budget (a rebuild into empty buffers sizes
// them exactly). Otherwise they get their records written in turn, the one begun in an earlier
// frame first, until the frame's budget is spent. Those
// whose last records are in stay in this frame's upload, appended with their records in place (in
// the order written); the others wait, their entities drawing the assets they replaced
// (collectAssetDemand, buildDraws). One round a frame: view regions prepare the frame again.
void HermiteCellFeature::uploadInParts(const engine::render::FrameContext& frame, AssetDemand& d) {
  if (waitingFrame_ != frame.frameNumber) {
    waitingFrame_ = frame.frameNumber;
    assetsWaiting_ = 0;
  }
  const auto isNew = [this](const std::shared_ptr<const SdfAsset>& a) { return !buffers_->entries.contains(a->id); };
  std::vector<std::shared_ptr<const SdfAsset>> queue;
  for (const auto& asset : d.wanted)
    if (isNew(asset)) queue.insert(partial_ && partial_->asset->id == asset->id ? queue.begin() : queue.end(), asset);
  std::uint64_t left = std::max<std::uint64_t>(1, settings_.uploadBytesPerFrame / kRecordUploadBytes);  // records
  std::uint64_t queued = 0;
  for (const auto& asset : queue) queued += asset->cells.records.size();
  if (queue.empty() || (queued <= left && !partial_)) {  // within the budget: uploaded whole, as without one
    if (!anotherRegionsPartial(frame)) partial_.reset();
    return;
  }
  std::erase_if(d.wanted, isNew);
  d.missing = bricksMissing(d, *buffers_);
  assetsWaiting_ += queue.size();
  if (partsFrame_ == frame.frameNumber || partsWait(frame, *queue.front())) return;
  partsFrame_ = frame.frameNumber;
  std::uint32_t base = buffers_->used.records;  // where the next asset's records go
  for (const auto& asset : queue) {
    if (!partial_ || partial_->asset->id != asset->id)
      partial_ = PartialUpload{asset, 0, frame.viewRegionIndex, frame.frameNumber, base};
    const auto total = static_cast<std::uint32_t>(asset->cells.records.size());
    const auto count = static_cast<std::uint32_t>(std::min<std::uint64_t>(total - partial_->written, left));
    if (!writeRecordPart(frame, count)) {  // refused, reported: not waiting any more
      --assetsWaiting_;
      break;
    }
    if (partial_->written < total) break;
    d.resident.emplace(asset->id, partial_->first);
    base = partial_->first + total;
    partial_.reset();
    d.wanted.push_back(asset);
    d.missing = true;
    --assetsWaiting_;
    left -= count;
    if (left == 0) break;
  }
}

// Whether this region's new assets (`first` of them to go first) wait without writing any this
// frame: a rebuild earlier in the frame copies records in its commands, not submitted yet (a part
// written now, in its own submission, runs before them: a buffer grown for it would lack them); or
// another region's asset is written in parts and this region's first is not it (begun instead, it
// began again whenever a new asset came to a region drawn before its own: a level streaming small
// assets into one side of a split starved a large one on the other side for good).
bool HermiteCellFeature::partsWait(const engine::render::FrameContext& frame, const SdfAsset& first) const {
  return pendingCopies_ || (anotherRegionsPartial(frame) && partial_->asset->id != first.id);
}

// Writes `count` more of the partial upload's records after those written; false when the
// allocation was refused: the asset is refused as a whole upload would be.
bool HermiteCellFeature::writeRecordPart(const engine::render::FrameContext& frame, std::uint32_t count) {
  // After the `written` records, each buffer made or grown with room for the whole asset, so that
  // the later parts are written in place.
  const std::shared_ptr<const SdfAsset> asset = partial_->asset;
  const AssetUpload::RecordSource part{asset.get(), matchingDerived(*asset), partial_->written, count};
  const auto total = static_cast<std::uint32_t>(asset->cells.records.size());
  std::vector<engine::gpu::BufferAppend> appends = recordAppends(*buffers_, std::span(&part, 1),
                                                                 partial_->first + partial_->written, total - partial_->written);
  auto replaced = engine::gpu::allocateOrRefuse([&] { return engine::gpu::appendToBuffers(*context_, appends); });
  if (!replaced) {
    partial_.reset();
    refuseNewAssets(frame, {asset}, replaced.error().message, VkDeviceSize(asset->cells.records.size()) * kRecordUploadBytes);
    return false;
  }
  // Commands recorded earlier (frames in flight) read the replaced buffers until their frames complete.
  for (Buffer& old : *replaced) frame.retire(std::move(old));
  partial_->written += count;
  partial_->frame = frame.frameNumber;
  uploadedBytes_ += VkDeviceSize(count) * kRecordUploadBytes;
  return true;
}

bool HermiteCellFeature::uploading() const { return assetsWaiting_ != 0; }

// Whether the asset written in parts is another view region's, written this frame or the last: that
// region goes on with it (a split screen's other side drawing the entity from its own asset), and a
// region without new assets must not drop it. Dropped, it began again every frame and was never whole.
bool HermiteCellFeature::anotherRegionsPartial(const engine::render::FrameContext& frame) const {
  return partial_ && partial_->region != frame.viewRegionIndex && partial_->frame + 1 >= frame.frameNumber;
}

// An asset not uploaded whose entity draws the asset it replaced meanwhile: refused, or waiting
// for its records to be written in parts (a budget per frame).
bool HermiteCellFeature::drawsPreviousAsset(std::uint64_t assetId) const {
  return refused_.contains(assetId) || settings_.uploadBytesPerFrame != 0;
}

// The asset the entity drew last frame stays uploaded, and drawn (buildDraws), while its new one is not.
void HermiteCellFeature::keepPreviousAsset(const engine::render::FrameContext& frame, engine::ecs::Entity entity,
                                           bool bricks, AssetDemand& d) {
  const std::uint64_t* previous = drawnAssets_.previous(entity);
  if (!previous) return;
  const auto kept = buffers_->entries.find(*previous);
  if (kept == buffers_->entries.end()) return;
  if (bricks) d.asBricks.insert(kept->first);
  if (d.seen.insert(kept->first).second) {
    d.wanted.push_back(kept->second.asset);
    kept->second.lastFrame = frame.frameNumber;
  }
}

// Whether the uploaded assets that no entity has drawn for Settings::releaseAfterFrames frames (at
// least the frames in flight) hold at least half of the uploaded records: then the buffers are
// rebuilt without them. A destroyed object's asset was held, CPU and GPU, until a new asset came.
bool HermiteCellFeature::idleAssetsToDrop(const engine::render::FrameContext& frame) const {
  const std::uint64_t idle = std::max<std::uint64_t>(settings_.releaseAfterFrames, frame.framesInFlight);
  std::uint64_t idleRecords = 0, records = 0;
  bool anyIdle = false;
  for (const auto& [id, entry] : buffers_->entries) {
    const std::uint64_t count = entry.asset->cells.records.size();
    records += count;
    if (frame.frameNumber - entry.lastFrame >= idle) {
      idleRecords += count;
      anyIdle = true;
    }
  }
  return anyIdle && 2 * idleRecords >= records;
}

// The assets the entities draw as cells (or keep drawing, for refused ones), and whether any upload is missing.
HermiteCellFeature::AssetDemand HermiteCellFeature::collectAssetDemand(const engine::render::FrameContext& frame) {
  AssetDemand d;
  frame.registry.view<HermiteSdfRenderable>().each([&](engine::ecs::Entity entity, const HermiteSdfRenderable& r) {
    if (!drawsCells(r.method) || !r.asset || r.asset->cells.records.empty()) return;
    const bool bricks = r.method == RenderMethod::CellBricks;
    if (!buffers_->entries.contains(r.asset->id) && drawsPreviousAsset(r.asset->id))
      keepPreviousAsset(frame, entity, bricks, d);
    if (refused_.contains(r.asset->id)) return;
    if (bricks) d.asBricks.insert(r.asset->id);
    if (!d.seen.insert(r.asset->id).second) return;
    d.wanted.push_back(r.asset);
    auto entry = buffers_->entries.find(r.asset->id);
    if (entry == buffers_->entries.end())
      d.missing = true;
    else
      entry->second.lastFrame = frame.frameNumber;
  });
  d.missing = d.missing || bricksMissing(d, *buffers_);  // an uploaded asset now drawn as bricks: upload its bricks
  return d;
}

static_assert(kProxySteps == int(CELL_PROXY_STEPS), "cells.h and hermite_host_device.h must agree");

// A multi-material asset's corner slots (one entry per record, the same for its fp32 and fp16
// records) and palette, where its entry finds them; an asset of one material adds nothing.
template <class Upload>
void appendMaterials(Upload& u, const SdfAsset& asset, CellBuffers::Entry& entry) {
  if (asset.palette.empty() || asset.cells.materials.size() != asset.cells.records.size()) return;
  entry.firstMaterialSlots = u.base.materialSlots + static_cast<std::uint32_t>(u.materialSlots.size());
  u.materialSlots.insert(u.materialSlots.end(), asset.cells.materials.begin(), asset.cells.materials.end());
  entry.firstPaletteEntry = u.base.palette + static_cast<std::uint32_t>(u.palette.size());
  for (const SdfMaterial& m : asset.palette)
    u.palette.push_back({m.baseColor, glm::vec4(m.roughness, m.metallic, 0.0f, 0.0f)});
}

// The asset's bricks, their cells (as indices into the record buffers) and cones, where its entry
// finds them; with none (`derived` null), the entry holds no brick and its bricks draw nothing.
template <class Upload>
void appendBricks(Upload& u, CellBuffers::Entry& entry, const CellDerived* derived) {
  entry.bricksUploaded = true;
  entry.firstBrick = u.base.bricks + static_cast<std::uint32_t>(u.bricks.size());
  if (!derived) return;
  for (shader::CellBrickGpu brick : derived->bricks.bricks) {
    brick.firstIndex += u.base.brickCells + static_cast<std::uint32_t>(u.brickCells.size());
    u.bricks.push_back(brick);
  }
  for (std::uint32_t record : derived->bricks.cellRecords) u.brickCells.push_back(entry.firstRecord + record);
  u.cones.insert(u.cones.end(), derived->brickCones.begin(), derived->brickCones.end());
}

// The bricks of the uploaded assets now drawn as bricks, appended to the upload (after the new
// assets' streams): the entries keep their records, rows and runs where they are. Returns each
// one's id and first brick, for its entry once the append succeeded.
template <class Upload>
std::vector<std::pair<std::uint64_t, std::uint32_t>> appendUploadedAssetsBricks(
    Upload& u, const CellBuffers& buffers, const std::unordered_set<std::uint64_t>& asBricks) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> firstBricks;
  for (std::uint64_t id : asBricks) {
    const auto uploaded = buffers.entries.find(id);
    if (uploaded == buffers.entries.end() || uploaded->second.bricksUploaded) continue;
    CellBuffers::Entry placed;  // where appendBricks puts them: after its records, whose place it needs
    placed.asset = uploaded->second.asset;
    placed.firstRecord = uploaded->second.firstRecord;
    appendBricks(u, placed, bricksOf(*placed.asset, derivedOrWarn(*placed.asset)));
    firstBricks.emplace_back(id, placed.firstBrick);
  }
  return firstBricks;
}

// Appends one asset's records, runs, bricks and cones to the upload, and its entry to `rebuilt`.
void HermiteCellFeature::appendAsset(CellBuffers& rebuilt, AssetUpload& u, const std::shared_ptr<const SdfAsset>& asset,
                                     const AssetDemand& d) const {
  CellBuffers::Entry entry;
  entry.asset = asset;
  entry.firstRecord = u.base.records + u.records;
  const CellDerived* derived = derivedOrWarn(*asset);
  const auto old = buffers_->entries.find(asset->id);
  entry.rows = old != buffers_->entries.end() ? old->second.rows : rowsOf(asset, derived);
  entry.runs = runsOf(asset, derived, settings_.maxRunLength);
  entry.firstRun = u.base.runs + u.runs;
  u.runSources.push_back({entry.runs.get(), entry.firstRecord});
  u.runs += static_cast<std::uint32_t>(entry.runs->size());
  if (d.asBricks.contains(asset->id) || (old != buffers_->entries.end() && old->second.bricksUploaded))
    appendBricks(u, entry, bricksOf(*asset, derived));
  // Where the buffers hold its records already: a kept asset's entry, or a new asset written in parts.
  std::optional<std::uint32_t> held;
  if (old != buffers_->entries.end())
    held = old->second.firstRecord;
  else if (const auto resident = d.resident.find(asset->id); resident != d.resident.end())
    held = resident->second;
  if (!held)
    u.recordSources.push_back({asset.get(), derived});
  else if (!u.recordsResident)  // a rebuild: copied on the GPU (an append leaves them in place)
    u.recordCopies.push_back({*held, entry.firstRecord, static_cast<std::uint32_t>(asset->cells.records.size()),
                              static_cast<std::uint32_t>(asset->cellsHalf.records.size())});
  u.records += static_cast<std::uint32_t>(asset->cells.records.size());
  u.halfRecords += static_cast<std::uint32_t>(asset->cellsHalf.records.size());
  appendMaterials(u, *asset, entry);
  rebuilt.entries.emplace(asset->id, std::move(entry));
}

// The rebuilt GPU buffers, made and filled in one submission; throws engine::gpu::VulkanError
// when an allocation fails.
void HermiteCellFeature::createAssetBuffers(CellBuffers& rebuilt, const AssetUpload& u) const {
  std::vector<engine::gpu::BufferAppend> appends = streamAppends(rebuilt, u, StreamCounts{});
  padEmptyBuffers(appends);
  (void)engine::gpu::appendToBuffers(*context_, appends);  // the buffers were empty: none replaced
}

// Appends the wanted assets not uploaded yet, and the bricks of uploaded assets now drawn as
// bricks, to the uploaded buffers, which grow when short, and leaves the uploaded ones where they
// are: a scene that streams assets in (and out) uploads each one once (a rebuild per new asset
// would copy every drawn asset: O(n) bytes a frame for a level that streams one asset in and one
// out per frame), and a switch to bricks copies the bricks alone, not every drawn asset's records
// again (the bunny at K = 256: 0.3-0.8 s on lavapipe). False when a rebuild is due: nothing
// uploaded yet, or the uploaded assets no longer drawn holding at least half of the records (the
// rebuild leaves them out, as the idle release does: at half, the uploads stay within twice what
// is dropped).
bool HermiteCellFeature::appendNewAssets(const engine::render::FrameContext& frame, const AssetDemand& d) {
  // New assets whose records were written in parts (uploadInParts: then they are the only new
  // ones) are appended even to empty buffers: a rebuild would write their records again.
  const bool resident = !d.resident.empty();
  if (buffers_->entries.empty() && !resident) return false;
  std::uint64_t idleRecords = 0;
  for (const auto& [id, entry] : buffers_->entries)
    if (!d.seen.contains(id)) idleRecords += entry.asset->cells.records.size();
  if (!buffers_->entries.empty() && 2 * idleRecords >= buffers_->used.records) return false;

  CellBuffers added;  // the new assets' entries
  AssetUpload u;
  u.base = buffers_->used;
  u.recordsResident = resident;
  for (const auto& asset : d.wanted)
    if (!buffers_->entries.contains(asset->id)) appendAsset(added, u, asset, d);
  const auto bricked = appendUploadedAssetsBricks(u, *buffers_, d.asBricks);
  std::vector<engine::gpu::BufferAppend> appends = streamAppends(*buffers_, u, buffers_->used);
  padEmptyBuffers(appends);  // the first asset, written in parts: the streams it has none of
  auto replaced = engine::gpu::allocateOrRefuse([&] { return engine::gpu::appendToBuffers(*context_, appends); });
  if (!replaced) {
    refuseNewAssets(frame, d.wanted, replaced.error().message, u.bytes());  // at least (drawn alone: no other asset's bytes)
    if (resident) partial_.reset();  // its records were written after the refused ones: written again
    return true;  // the buffers stay as they were: what was drawn is drawn
  }
  // Commands recorded earlier (this frame's earlier view regions, frames in flight) read the
  // replaced buffers until their frames complete.
  for (Buffer& old : *replaced) frame.retire(std::move(old));
  for (auto& [id, entry] : added.entries) {
    entry.lastFrame = frame.frameNumber;
    buffers_->entries.emplace(id, std::move(entry));
  }
  for (const auto& [id, firstBrick] : bricked) {
    CellBuffers::Entry& entry = buffers_->entries.at(id);
    entry.bricksUploaded = true;
    entry.firstBrick = firstBrick;
  }
  if (buffers_->entries.size() == added.entries.size()) buffers_->runLength = settings_.maxRunLength;  // the first
  buffers_->used = u.end();
  buffers_->bytes += u.bytes();
  uploadedBytes_ += u.writtenBytes();
  engine::log::debug("hermite cells: {} assets and the bricks of {} appended, {} records uploaded ({} in all)",
                     added.entries.size(), bricked.size(), u.records, buffers_->used.records);
  return true;
}

// A rebuild while an asset is written in parts carries its records written so far over (after the
// rebuilt records, copied on the GPU), with room for the rest: a new run length or idle assets
// dropped meanwhile began the upload again from its first record.
void HermiteCellFeature::carryPartialUpload(AssetUpload& u) const {
  if (!partial_) return;
  const SdfAsset& asset = *partial_->asset;
  u.carried = {partial_->first, u.records, partial_->written,
               static_cast<std::uint32_t>(clippedCount(asset.cellsHalf.records.size(), 0, partial_->written))};
  u.carriedRoom = static_cast<std::uint32_t>(asset.cells.records.size());
}

// Records in this frame's commands the copies of the kept assets' per-record streams (fp32 and
// fp16 records, cell cones) from the `old` buffers into the rebuilt ones (buffers_), before the
// culling passes and draws that read them: a rebuild writes from the CPU only the assets the old
// buffers lack. The old buffers are retired, or held until this frame is submitted.
void HermiteCellFeature::copyResidentRecords(const engine::render::FrameContext& frame,
                                             std::unique_ptr<CellBuffers> old, const AssetUpload& u) {
  const std::vector<AssetUpload::RecordCopy> recordCopies = u.allCopies();
  if (recordCopies.empty()) return frame.retire(std::move(old));
  const auto stream = [&](const Buffer& from, const Buffer& to, std::size_t size, bool half) {
    engine::gpu::BufferCopy copy{&from, &to, {}};
    for (const AssetUpload::RecordCopy& c : recordCopies)
      if (const std::uint32_t count = half ? c.halfRecords : c.records; count != 0)
        copy.regions.push_back({VkDeviceSize(c.from) * size, VkDeviceSize(c.to) * size, VkDeviceSize(count) * size});
    return copy;
  };
  std::vector<engine::gpu::BufferCopy> copies{
      stream(old->records[0], buffers_->records[0], sizeof(CellRecord), false),
      stream(old->records[1], buffers_->records[1], sizeof(CellRecordHalf), true),
      stream(old->cellCones, buffers_->cellCones, sizeof(shader::CellBrickCone), false),
  };
  engine::gpu::recordBufferCopies(frame.cmd, copies);
  pendingCopies_ = PendingCopies{frame.frameNumber, frame.viewRegionIndex, std::move(old), std::move(copies)};
}

// A rebuild's copies recorded in an earlier frame: that frame was submitted (a later frame number),
// and the old buffers go with the frames in flight; or it failed while it was recorded and this is
// its next try (the same number, from a view region no later than the one that recorded them):
// recorded again, the rebuilt buffers holding nothing of the kept records until they run.
void HermiteCellFeature::settlePendingCopies(const engine::render::FrameContext& frame) {
  if (!pendingCopies_) return;
  if (frame.frameNumber != pendingCopies_->frameNumber) {
    frame.retire(std::move(pendingCopies_->from));
    pendingCopies_.reset();
    return;
  }
  if (frame.viewRegionIndex > pendingCopies_->region) return;  // a later view region of the same frame
  engine::gpu::recordBufferCopies(frame.cmd, pendingCopies_->copies);
  pendingCopies_->region = frame.viewRegionIndex;
}

// Replaces the feature's buffers with the rebuilt ones, retiring the old for frames in flight.
void HermiteCellFeature::commitAssetBuffers(const engine::render::FrameContext& frame, CellBuffers rebuilt,
                                            const AssetUpload& u) {
  rebuilt.runLength = settings_.maxRunLength;
  rebuilt.bytes = u.bytes();
  uploadedBytes_ += u.writtenBytes();
  copiedBytes_ += u.copiedBytes();
  for (auto& [id, entry] : rebuilt.entries) entry.lastFrame = frame.frameNumber;
  if (partial_) partial_->first = u.carried.to;  // carried over (carryPartialUpload)
  copyResidentRecords(frame, std::exchange(buffers_, std::make_unique<CellBuffers>(std::move(rebuilt))), u);
  engine::log::debug("hermite cells: {} assets, {} records uploaded", buffers_->entries.size(), u.records);
}

// The rebuilt buffers (`needed` bytes) did not fit in GPU memory. The assets this rebuild was for
// (new ones, or a new run length) are refused, each reported once, and not tried again until
// memory is given back (forgetRefusalsThatMayFit); the assets already uploaded keep drawing from
// the old buffers.
void HermiteCellFeature::refuseNewAssets(const engine::render::FrameContext& frame,
                                         const std::vector<std::shared_ptr<const SdfAsset>>& wanted,
                                         const std::string& why, VkDeviceSize needed) {
  const engine::gpu::MemoryRefusal refusal(context_->allocator(), needed);
  bool refusedAny = false;
  for (const auto& asset : wanted) {
    if (buffers_->entries.contains(asset->id)) continue;
    refused_.insert_or_assign(asset->id, refusal);
    refusedAny = true;
    frame.reportDropped(fmt::format("hermite cells: '{}' ({} cells) is not drawn: out of GPU memory ({})", asset->name,
                                    asset->cells.records.size(), why));
  }
  if (refusedAny) return;
  refusedRunLength_ = settings_.maxRunLength;
  runsRefusal_ = refusal;
  frame.reportDropped(fmt::format("hermite cells: cell runs of length {} are not built: out of GPU memory ({}); the "
                                  "runs of length {} stay",
                                  settings_.maxRunLength, why, buffers_->runLength));
}

}  // namespace hsdf
