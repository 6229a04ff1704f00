#pragma once
// Test scripts for the Viewer (scene_runner --script FILE): lines "frame N: key=value ..." whose
// settings go through setTuningValues -> Viewer::checkTuning -> Viewer::setTuning, the path the
// panel takes (the settings of a line that follow one another are one change), and whose
// actions are the panel's buttons. So a ctest under Xvfb drives every control. Format:
//
//   # comment
//   frame 0: method=cells subdivisions=2 debug_view=normals
//   frame 3: resolution=32 wait-bake screenshot=out/k32.png
//   frame 5: resolution=48 cancel-bake
//
// Tuning keys: those of a settings file (tuning.h). Actions: screenshot=PATH (PNG + .json
// settings sidecar), wait-bake (also the compared side's bake and the levels of detail),
// cancel-bake, reload-shaders (the pipelines from the SPIR-V on disk, the result logged),
// rebuild-shaders (the panel's button and
// F5: the build's shader target first, then the reload), shader-dir=PATH (SPIR-V from PATH from
// now on, as HSDF_SHADER_DIR=PATH: a reload from a broken copy), size=WxH (1..4096; the window
// system applies it asynchronously), wait-size (waits until the window has the last size asked for),
// minimize, restore (the window manager iconifies / restores the window; the action waits until it
// has), present-fault=out-of-date|suboptimal (the next present reports that: vk_check.h's fault
// injection), fail-frame (the next frame fails while it is recorded: GPU memory runs out at its
// vkEndCommandBuffer, the same injection; the renderer skips that frame), panel=on|off, vsync=on|off, fullscreen=on|off, view=0..7 (orbit view), camera=orbit|fly
// (keeps the view), scene-camera=NAME|INDEX (look through a glTF camera node; an unknown one fails
// the run when it comes, naming the scene's cameras), save-settings=PATH, load-settings=PATH.
// Commands of a frame run in order before that frame is drawn (frame 0: the first). "frame N" counts
// steps of the frame loop: a minimised window's steps draw nothing but count, so a script can
// restore the window it minimised.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/expected.h"

namespace samples {

class Viewer;

struct ScriptCommand {
  std::string key;
  std::string value;  // empty for wait-bake, cancel-bake
  int line = 0;
};

struct ScriptFrame {
  std::uint64_t frame = 0;
  std::vector<ScriptCommand> commands;
};

struct Script {
  std::string name;                 // the file, for messages
  std::vector<ScriptFrame> frames;  // by frame number, ascending
  std::uint64_t lastFrame() const { return frames.empty() ? 0 : frames.back().frame; }
};

// Errors name the file, the line and what is wrong (unknown key, bad value, frame out of order).
engine::Expected<Script> parseScript(std::string_view text, const std::string& name);
engine::Expected<Script> loadScript(const std::filesystem::path& file);

// Runs the commands of `frame` on the viewer. A failed bake (cancelled, over budget) is logged, not
// an error: scripts test those on purpose. Errors: a setting the viewer refuses, a file that cannot
// be read or written.
engine::Status runScriptFrame(const Script& script, const ScriptFrame& frame, Viewer& viewer);

}  // namespace samples
