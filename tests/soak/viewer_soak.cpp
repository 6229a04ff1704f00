// Soak test: the shared frame step (samples::Viewer) for many frames, headless and small, while the
// scene changes underneath it the way an editor session would: re-bakes at another K on the bake
// job's worker thread, method switches (cells, trilinear, hermite, mesh), n and normal mode
// changes, an extra baked object added and removed, the split view (two view regions, the compared
// side drawn from its own bake at 2K) switched on with the extra object and off at the mesh. Host RSS (/proc/self/statm) and the GPU
// allocator's totals are sampled every 100 frames. A bake started by one frame is put in the scene by
// the next (waitForRunningBakes), so every frame draws the same state whatever the machine's load.
//
// Why the check compares samples one cycle apart: the schedule of changes repeats every
// `cycle` frames, so two samples a whole cycle apart see the same scene (same K, method and
// objects). A leak then shows as growth between them, while the legitimate ups and downs inside a
// cycle (a K = 24 field costs more than a K = 16 one) cancel out. The first cycle is warm-up
// (pipelines, grow-only buffers and textures a method makes the first time it draws: a sample
// taken before the first trilinear frame cannot be compared with one after), the second is the
// baseline, and every later sample is compared with the baseline sample of the same phase:
//   - GPU memory in use and the number of live allocations must be equal (no tolerance: the
//     allocator is deterministic, a single leaked buffer fails);
//   - GPU memory reserved (blocks) must not exceed the baseline cycle's peak;
//   - host RSS may grow by at most --rss-tolerance-mb (default 8 MiB) between two such samples:
//     malloc arenas and the driver's caches settle late, so the host gets a tolerance. For scale,
//     each cycle bakes a K = 16 and a K = 24 field and a K = 12 sphere (16 B a sample: 64 KiB +
//     216 KiB + 27 KiB): a leak of one field per cycle passes 8 MiB only after about 27 cycles, but
//     a leaked asset also keeps its GPU copy, which the exact GPU check catches at once.
// Runs on the device HSDF_TEST_DEVICE names (gpu|lavapipe|auto; unset: lavapipe).
// Exit code 0 when every check holds and the validation layers stayed silent, 1 otherwise.
//
//   viewer_soak [--frames N] [--period P] [--size WxH] [--rss-tolerance-mb M] [--csv FILE]
//               [--validation on|off]   (default on; off: to tell the layers' own growth from ours)
//               [--scene FILE.glb] [--objects on|off]  (default off; on: each mesh its own SDF object)
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "engine/core/expected.h"
#include "engine/gpu/memory.h"
#include "engine/scene/transform.h"
#include "hermite_sdf/core/bake_job.h"
#include "options_common.h"
#include "test_device.h"
#include "viewer.h"

namespace {

using engine::Expected;
using engine::Status;
using engine::makeError;

struct Options {
  std::uint64_t frames = 1000;
  std::uint64_t period = 20;  // frames between two scene changes
  std::uint32_t width = 160;
  std::uint32_t height = 120;
  double rssToleranceMb = 8.0;
  std::filesystem::path csv;
  bool validation = true;
  std::filesystem::path gltf = HSDF_TEST_DATA_DIR "/gltf/bunny_small.glb";
  // --objects on: the scene's meshes as separate SDF objects (SceneDesc::objects, baked once when
  // the scene loads: the schedule's re-bakes then change nothing); off: baked whole, side by side.
  bool objects = false;
};

Expected<std::uint64_t> parseCount(std::string_view option, std::string_view text) {
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value == 0)
    return makeError(fmt::format("{}: expected a positive integer, got '{}'", option, text));
  return value;
}

Expected<Options> parseOptions(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string_view option = argv[i];
    if (i + 1 >= argc) return makeError(fmt::format("{}: missing value", option));
    const std::string_view value = argv[++i];
    if (option == "--frames") {
      ENGINE_TRY_ASSIGN(options.frames, parseCount(option, value));
    } else if (option == "--period") {
      ENGINE_TRY_ASSIGN(options.period, parseCount(option, value));
    } else if (option == "--size") {
      ENGINE_TRY_ASSIGN(const samples::ImageSize size, samples::parseImageSize(option, value, samples::kMaxWindowDimension));
      options.width = size.width;
      options.height = size.height;
    } else if (option == "--rss-tolerance-mb") {
      ENGINE_TRY_ASSIGN(const std::uint64_t mb, parseCount(option, value));
      options.rssToleranceMb = double(mb);
    } else if (option == "--csv") {
      options.csv = std::string(value);
    } else if (option == "--validation") {
      if (value != "on" && value != "off") return makeError(fmt::format("--validation: on or off, got '{}'", value));
      options.validation = value == "on";
    } else if (option == "--scene") {
      options.gltf = std::string(value);
      if (!std::filesystem::is_regular_file(options.gltf)) return makeError(fmt::format("--scene: no file '{}'", value));
    } else if (option == "--objects") {
      if (value != "on" && value != "off") return makeError(fmt::format("--objects: on or off, got '{}'", value));
      options.objects = value == "on";
    } else {
      return makeError(fmt::format("unknown option '{}' (--frames, --period, --size, --rss-tolerance-mb, --csv, "
                                   "--validation, --scene, --objects)",
                                   option));
    }
  }
  return options;
}

struct Sample {
  std::uint64_t frame = 0;
  std::uint64_t rssBytes = 0;
  engine::gpu::AllocatorStats gpu;
  std::size_t sdfObjects = 0;
  int resolution = 0;
};

// The process's resident bytes, after glibc has given back the free memory it keeps: the bake's
// worker threads allocate in per-thread arenas, and how many arenas a run touches depends on how
// the threads happen to be scheduled (a CI run under load grew 56 MiB once, at frame 300 of the
// scene-objects soak, and never again). malloc_trim(0) returns the free pages of every arena, so the
// samples compare memory in use (a leak stays resident), not the allocator's spare capacity.
std::uint64_t residentBytes() {
  malloc_trim(0);
  std::ifstream statm("/proc/self/statm");
  std::uint64_t size = 0, resident = 0;
  statm >> size >> resident;
  return resident * std::uint64_t(sysconf(_SC_PAGESIZE));
}

// The scene changes, applied in turn one every `period` frames; the list repeats (one cycle).
enum class Change { Rebake24, Trilinear, MoreSubdivisions, AddObject, Hermite, Rebake16, CentralNormals, Mesh,
                    RemoveObject, BackToCells };
constexpr Change kSchedule[] = {Change::Rebake24,       Change::Trilinear, Change::MoreSubdivisions,
                                Change::AddObject,      Change::Hermite,   Change::Rebake16,
                                Change::CentralNormals, Change::Mesh,      Change::RemoveObject,
                                Change::BackToCells};
constexpr std::uint64_t kChangesPerCycle = std::size(kSchedule);

class Soak {
 public:
  explicit Soak(samples::Viewer& viewer) : viewer_(viewer) {}

  Status apply(Change change) {
    samples::TuningState tuning = viewer_.tuning();
    switch (change) {
      case Change::Rebake24: tuning.resolution = 24; break;
      case Change::Rebake16: tuning.resolution = 16; break;
      case Change::Trilinear: tuning.method = hsdf::RenderMethod::TrilinearSphereTrace; break;
      case Change::Hermite: tuning.method = hsdf::RenderMethod::HermiteSphereTrace; break;
      case Change::Mesh:  // and the split view off
        tuning.method = samples::Method::Mesh;
        tuning.split = samples::SplitMode::Off;
        break;
      case Change::MoreSubdivisions: tuning.subdivisions = 4; break;
      case Change::CentralNormals: tuning.normals = hsdf::NormalMode::CentralDifferences; break;
      case Change::BackToCells:
        tuning.method = hsdf::RenderMethod::Cells;
        tuning.subdivisions = 3;
        tuning.normals = hsdf::NormalMode::Exact;
        break;
      case Change::AddObject:  // and the split view on: two view regions, the compared side from its own bake at 2K
        tuning.split = samples::SplitMode::Vertical;
        tuning.compareMethod = hsdf::RenderMethod::TrilinearSphereTrace;
        viewer_.setTuning(tuning);
        return addObject();
      case Change::RemoveObject: return removeObject();
    }
    viewer_.setTuning(tuning);
    return {};
  }

  // A second, separately baked SDF (its own asset: uploaded on its first frame, freed when removed).
  Status addObject() {
    hsdf::BakeSettings settings;
    settings.resolution = 12;
    ENGINE_TRY_ASSIGN(std::shared_ptr<const hsdf::SdfAsset> asset,
                      hsdf::bakeAsset(hsdf::BakeSource::fromShape("sphere"), settings));
    hsdf::HermiteSdfRenderable renderable;
    renderable.asset = std::move(asset);
    samples::applyTuning(viewer_.tuning(), renderable);
    engine::ecs::Registry& registry = viewer_.registry();
    extra_ = registry.create();
    engine::scene::Transform transform;
    transform.translation = viewer_.boundsMax();  // beside the scene, inside the orbit view
    registry.emplace<engine::scene::Transform>(*extra_, transform);
    registry.emplace<hsdf::HermiteSdfRenderable>(*extra_, std::move(renderable));
    return {};
  }

  Status removeObject() {
    if (!extra_) return makeError("soak schedule: removing an object that was not added");
    viewer_.registry().destroy(*extra_);
    extra_.reset();
    return {};
  }

  Sample sample(std::uint64_t frame) {
    Sample s;
    s.frame = frame;
    s.rssBytes = residentBytes();
    s.gpu = viewer_.context().allocator().stats();
    viewer_.registry().view<hsdf::HermiteSdfRenderable>().each(
        [&s](engine::ecs::Entity, const hsdf::HermiteSdfRenderable&) { ++s.sdfObjects; });
    s.resolution = viewer_.sdfAsset() ? int(viewer_.sdfAsset()->field.grid.resolution) : 0;
    return s;
  }

 private:
  samples::Viewer& viewer_;
  std::optional<engine::ecs::Entity> extra_;
};

std::string describe(const Sample& s) {
  return fmt::format("frame {:6}: RSS {:8.2f} MiB, GPU used {:8.3f} MiB in {:4} allocations, reserved {:6.1f} MiB, "
                     "{} SDF objects, K {}",
                     s.frame, double(s.rssBytes) / (1 << 20), double(s.gpu.usedBytes) / (1 << 20),
                     s.gpu.allocationCount, double(s.gpu.reservedBytes) / (1 << 20), s.sdfObjects, s.resolution);
}

// The checks of the header comment; each failure is printed. Returns whether all held.
bool checkGrowth(const std::vector<Sample>& samples, std::uint64_t samplesPerCycle, double rssToleranceMb) {
  if (samples.size() <= 2 * samplesPerCycle) {
    std::printf("FAIL: %zu samples: nothing after the warm-up and baseline cycles (%llu samples each); run more "
                "frames\n",
                samples.size(), static_cast<unsigned long long>(samplesPerCycle));
    return false;
  }
  bool ok = true;
  std::uint64_t baselineReservedPeak = 0;
  for (std::uint64_t i = samplesPerCycle; i < 2 * samplesPerCycle; ++i)
    baselineReservedPeak = std::max(baselineReservedPeak, samples[i].gpu.reservedBytes);
  double worstRssGrowthMb = 0.0;
  for (std::size_t i = 2 * samplesPerCycle; i < samples.size(); ++i) {
    const Sample& now = samples[i];
    const Sample& then = samples[samplesPerCycle + i % samplesPerCycle];
    if (now.gpu.usedBytes != then.gpu.usedBytes || now.gpu.allocationCount != then.gpu.allocationCount) {
      std::printf("FAIL: GPU memory in use grew at the same scene state:\n  %s\n  %s\n", describe(then).c_str(),
                  describe(now).c_str());
      ok = false;
    }
    if (now.gpu.reservedBytes > baselineReservedPeak) {
      std::printf("FAIL: GPU memory reserved above the baseline peak %llu B:\n  %s\n",
                  static_cast<unsigned long long>(baselineReservedPeak), describe(now).c_str());
      ok = false;
    }
    const double growthMb = (double(now.rssBytes) - double(then.rssBytes)) / (1 << 20);
    worstRssGrowthMb = std::max(worstRssGrowthMb, growthMb);
    if (growthMb > rssToleranceMb) {
      std::printf("FAIL: host RSS grew %.2f MiB (tolerance %.0f MiB) at the same scene state:\n  %s\n  %s\n",
                  growthMb, rssToleranceMb, describe(then).c_str(), describe(now).c_str());
      ok = false;
    }
  }
  const Sample& baselineEnd = samples[2 * samplesPerCycle - 1];
  const Sample& last = samples.back();
  std::uint64_t reservedPeak = 0;
  for (const Sample& s : samples) reservedPeak = std::max(reservedPeak, s.gpu.reservedBytes);
  std::printf("compared frames %llu .. %llu with the baseline cycle (frames %llu .. %llu): worst RSS growth at the "
              "same scene state %.2f MiB (tolerance %.0f MiB); RSS %.2f -> %.2f MiB; GPU used %llu -> %llu B, "
              "allocations %llu -> %llu, reserved peak %llu B (baseline %llu B)\n",
              static_cast<unsigned long long>(samples[2 * samplesPerCycle].frame),
              static_cast<unsigned long long>(last.frame),
              static_cast<unsigned long long>(samples[samplesPerCycle].frame),
              static_cast<unsigned long long>(baselineEnd.frame), worstRssGrowthMb, rssToleranceMb,
              double(baselineEnd.rssBytes) / (1 << 20), double(last.rssBytes) / (1 << 20),
              static_cast<unsigned long long>(baselineEnd.gpu.usedBytes),
              static_cast<unsigned long long>(last.gpu.usedBytes),
              static_cast<unsigned long long>(baselineEnd.gpu.allocationCount),
              static_cast<unsigned long long>(last.gpu.allocationCount),
              static_cast<unsigned long long>(reservedPeak), static_cast<unsigned long long>(baselineReservedPeak));
  return ok;
}

Status writeCsv(const std::filesystem::path& path, const std::vector<Sample>& samples) {
  std::ofstream out(path);
  if (!out) return makeError(fmt::format("--csv {}: cannot write", path.string()));
  out << "frame,rss_bytes,gpu_used_bytes,gpu_allocations,gpu_reserved_bytes,sdf_objects,resolution\n";
  for (const Sample& s : samples)
    out << fmt::format("{},{},{},{},{},{},{}\n", s.frame, s.rssBytes, s.gpu.usedBytes, s.gpu.allocationCount,
                       s.gpu.reservedBytes, s.sdfObjects, s.resolution);
  return {};
}

constexpr std::uint64_t kSampleEvery = 100;

// Blocks until the bakes running now (the main field's re-bake, the compared side's bake) are done,
// without putting them in the scene: the next step does, through the Viewer's own path, as when a
// bake is quick. Each bake then goes in at the frame after the one that started it, and every frame
// draws the same state in every run whatever the machine's load. Left to the worker threads' pace,
// the state at a sample depended on it (seen on a machine loaded 7-11 deep on 2 cores): a compared
// side's bake still running at the sample left the main asset's trilinear texture (the compared
// side's stand-in) alive, and a main re-bake done only after the switch away from cells 20 frames
// later left the cells holding the older, smaller field; either made one sample differ from the
// same phase a cycle later ("GPU memory in use grew", less or more).
void waitForRunningBakes(samples::Viewer& viewer) {
  for (hsdf::BakeJob* job : {viewer.bakeJob(), viewer.compareBakeJob()})
    if (job) job->waitUntilDone();
}

Expected<bool> runSoak(const Options& options) {
  const std::uint64_t cycle = options.period * kChangesPerCycle;
  if (cycle % kSampleEvery != 0)
    return makeError(fmt::format("--period {}: a cycle of {} changes must last a multiple of {} frames",
                                 options.period, kChangesPerCycle, kSampleEvery));
  samples::ViewerDesc desc;
  desc.width = options.width;
  desc.height = options.height;
  desc.headless = true;
  desc.validation = options.validation;
  // The test device: HSDF_TEST_DEVICE=gpu|lavapipe|auto, lavapipe unless set (tests/support).
  ENGINE_TRY_ASSIGN(desc.device, hsdftest::testDevicePreference());
  ENGINE_TRY_ASSIGN(std::unique_ptr<samples::Viewer> viewer, samples::Viewer::create(desc));
  samples::SceneDesc scene;
  scene.gltf = options.gltf;
  scene.objects = options.objects;
  scene.sideBySide = !options.objects;  // the meshes and their SDF side by side: every method has something to draw
  samples::TuningState tuning;
  tuning.resolution = 16;
  ENGINE_TRY(viewer->loadScene(scene, tuning));
  viewer->setOrbitView(1);

  Soak soak(*viewer);
  std::vector<Sample> samples;
  for (std::uint64_t frame = 1; frame <= options.frames; ++frame) {
    if (frame % options.period == options.period / 2) {  // changes halfway between samples
      const Change change = kSchedule[(frame / options.period) % kChangesPerCycle];
      ENGINE_TRY(soak.apply(change).withContext(fmt::format("frame {}", frame)));
    }
    ENGINE_TRY(viewer->step().withContext(fmt::format("frame {}", frame)));
    waitForRunningBakes(*viewer);
    if (frame % kSampleEvery == 0) {
      if (!viewer->bakeError().empty()) return makeError("re-bake failed: " + viewer->bakeError());
      samples.push_back(soak.sample(frame));
      std::printf("%s\n", describe(samples.back()).c_str());
      std::fflush(stdout);
    }
  }
  if (!options.csv.empty()) ENGINE_TRY(writeCsv(options.csv, samples));
  const bool grew = !checkGrowth(samples, cycle / kSampleEvery, options.rssToleranceMb);
  ENGINE_TRY(viewer->close());  // an error when the validation layers said anything
  return !grew;
}

}  // namespace

int main(int argc, char** argv) {
  const Expected<Options> options = parseOptions(argc, argv);
  if (!options) {
    std::fprintf(stderr, "viewer_soak: %s\n", options.error().message.c_str());
    return 2;
  }
  const Expected<bool> passed = runSoak(*options);
  if (!passed) {
    std::fprintf(stderr, "viewer_soak: FAIL: %s\n", passed.error().message.c_str());
    return 1;
  }
  std::printf("%s\n", *passed ? "PASS" : "FAIL");
  return *passed ? 0 : 1;
}
