#include "screenshots.h"

#include "engine/core/image_io.h"
#include "engine/core/log.h"
#include "engine/render/renderer.h"
#include "sdf_stats.h"

namespace samples {

using namespace engine;

Status Screenshots::write(render::Renderer& renderer, const std::filesystem::path& path, const ScreenshotContent& content) {
  renderer.finish();
  const std::vector<std::uint8_t> pixels = renderer.readbackColor();
  const VkExtent2D extent = renderer.extent();
  ENGINE_TRY(writePng(path, pixels, extent.width, extent.height, 4));
  std::filesystem::path sidecar = path;
  sidecar.replace_extension(".json");
  const TuningState& tuning = content.tuning;
  ENGINE_TRY(saveTuning(sidecar, tuning));
  const hsdf::SdfAsset* asset = content.asset;
  log::info("screenshot: {} ({}x{}, {}{}{})", path.string(), extent.width, extent.height, methodName(tuning.method),
            asset ? "; " : "", asset ? describeSdfStats(sdfStats(*asset)) : "");
  if (tuning.split != SplitMode::Off)
    log::info("screenshot: {}: split {} at {:.2f}: {} K {} | {} K {} ({} normals)", path.string(), splitModeName(tuning.split),
              tuning.splitPosition, methodName(tuning.method), content.resolution, methodName(tuning.compareMethod),
              content.compareResolution, normalModeName(tuning.compareNormals));
  if (const NormalDifference* difference = content.difference)
    log::info("screenshot: {}: difference {} vs {}: mean {:.3f} deg, max {:.3f} deg over {} pixels; coverage differs in "
              "{} of {} covered pixels ({:.4f})",
              path.string(), methodName(tuning.method), methodName(tuning.compareMethod), difference->meanDegrees,
              difference->maxDegrees, difference->coveredBoth, difference->coverageDiffers, difference->coveredEither,
              difference->coverageDiffersShare());
  return {};
}

void Screenshots::writeRequested(const std::function<Status(const std::filesystem::path&)>& write) {
  if (!pending_) return;
  const std::filesystem::path path = std::move(*pending_);
  pending_.reset();
  const Status written = write(path);
  statusLine_ = written ? "wrote " + path.string() : written.error().message;
  if (!written) log::warn("{}", written.error().message);
}

}  // namespace samples
