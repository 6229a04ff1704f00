#pragma once
// Screenshots of the Viewer's frames: the last frame as a PNG, the tuning beside it as a settings
// file (same name, .json: --settings loads it) and what the frame showed in the log (the SDF's
// statistics, the split, the difference numbers). A request (the panel's button) is written after
// the next frame; the status line says how it went.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "engine/core/expected.h"
#include "difference_view.h"
#include "tuning.h"

namespace engine::render {
class Renderer;
}

namespace samples {

// What the frame on screen shows, for the screenshot's log lines.
struct ScreenshotContent {
  const TuningState& tuning;
  const hsdf::SdfAsset* asset = nullptr;  // the main side's SDF, or null
  int resolution = 0;                     // the K the main side is drawn with
  int compareResolution = 0;              // the K the compared side is drawn with
  const NormalDifference* difference = nullptr;  // the last difference-view frame's numbers, or null
};

class Screenshots {
 public:
  // Waits for the GPU and writes the renderer's last frame, its settings file and the log lines.
  static engine::Status write(engine::render::Renderer& renderer, const std::filesystem::path& path,
                              const ScreenshotContent& content);

  void request(std::filesystem::path path) { pending_ = std::move(path); }
  // After a frame: the requested screenshot, through `write`; the status line and the log say how
  // it went.
  void writeRequested(const std::function<engine::Status(const std::filesystem::path&)>& write);
  // What the last requested screenshot or settings file operation said ("wrote x.png", an error).
  const std::string& statusLine() const { return statusLine_; }
  void setStatusLine(std::string line) { statusLine_ = std::move(line); }

 private:
  std::optional<std::filesystem::path> pending_;
  std::string statusLine_;
};

}  // namespace samples
