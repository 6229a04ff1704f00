#include "script.h"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "engine/core/files.h"
#include "engine/core/log.h"
#include "engine/gpu/vk_check.h"
#include "options_common.h"
#include "tuning.h"
#include "viewer.h"

namespace samples {
namespace {

using engine::Status;

constexpr std::string_view kValueActions[] = {"screenshot", "size",          "panel",         "vsync",  "fullscreen",
                                              "view",       "save-settings", "load-settings", "camera", "shader-dir",
                                              "present-fault", "scene-camera"};
constexpr std::string_view kBareActions[] = {"wait-bake", "cancel-bake", "reload-shaders", "rebuild-shaders", "minimize",
                                             "restore",   "wait-size",   "fail-frame"};

template <std::size_t N>
bool contains(const std::string_view (&list)[N], std::string_view key) {
  return std::find(std::begin(list), std::end(list), key) != std::end(list);
}

bool parseInt(std::string_view text, int& out) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), out);
  return error == std::errc() && end == text.data() + text.size();
}

// size=WxH, each 1..4096 (1x1: the smallest framebuffer a window has; 0x0 comes from minimising).
engine::Expected<ImageSize> parseWindowSize(std::string_view text) {
  return parseImageSize("size", text, kMaxWindowDimension);
}

// present-fault=out-of-date|suboptimal: what the next present reports.
std::optional<VkResult> presentFault(std::string_view text) {
  if (text == "out-of-date") return VK_ERROR_OUT_OF_DATE_KHR;
  if (text == "suboptimal") return VK_SUBOPTIMAL_KHR;
  return std::nullopt;
}

bool parseOnOff(std::string_view text, bool& out) {
  if (text != "on" && text != "off") return false;
  out = text == "on";
  return true;
}

bool isTuning(const ScriptCommand& c) { return isTuningKey(c.key); }

// Settings that follow one another on a line are one change, checked and applied together (as the
// keys of a settings file): "padding=16 resolution=40" from K = 16 is the same as the other order.
// Returns the end of the run of settings that starts at `begin`.
std::vector<ScriptCommand>::const_iterator settingsRun(std::vector<ScriptCommand>::const_iterator begin,
                                                       std::vector<ScriptCommand>::const_iterator end) {
  return std::find_if_not(begin, end, isTuning);
}

Status applySettings(std::vector<ScriptCommand>::const_iterator begin, std::vector<ScriptCommand>::const_iterator end,
                     TuningState& tuning) {
  std::vector<TuningAssignment> values;
  for (auto c = begin; c != end; ++c) values.push_back({c->key, c->value});
  return setTuningValues(tuning, values);
}

// Checks one action's key and value.
Status checkAction(const ScriptCommand& c) {
  if (contains(kBareActions, c.key)) {
    if (!c.value.empty()) return engine::makeError(fmt::format("'{}' takes no value", c.key));
    return {};
  }
  if (!contains(kValueActions, c.key))
    return engine::makeError(fmt::format("unknown key '{}' (settings: {}; actions: screenshot, size, panel, vsync, "
                                         "fullscreen, view, camera, scene-camera, save-settings, load-settings, shader-dir, present-fault, "
                                         "wait-bake, cancel-bake, reload-shaders, rebuild-shaders, minimize, restore, wait-size, "
                                         "fail-frame)",
                                         c.key, tuningKeyList()));
  bool flag = false;
  int view = 0;
  if (c.value.empty()) return engine::makeError(fmt::format("'{}' needs a value ({}=...)", c.key, c.key));
  if (c.key == "size") ENGINE_TRY(parseWindowSize(c.value));
  if ((c.key == "panel" || c.key == "vsync" || c.key == "fullscreen") && !parseOnOff(c.value, flag))
    return engine::makeError(fmt::format("{} '{}' is not on or off", c.key, c.value));
  if (c.key == "view" && !(parseInt(c.value, view) && view >= 0 && view <= 7))
    return engine::makeError(fmt::format("view '{}' is not 0..7", c.value));
  if (c.key == "present-fault" && !presentFault(c.value))
    return engine::makeError(fmt::format("present-fault '{}' is not out-of-date or suboptimal", c.value));
  if (c.key == "camera" && c.value != "orbit" && c.value != "fly")
    return engine::makeError(fmt::format("camera '{}' is not orbit or fly", c.value));
  return {};
}

// "frame N: commands" -> the frame number and the commands' text.
Status parseFrameLine(const std::string& line, std::uint64_t& frame, std::string& rest) {
  const std::size_t colon = line.find(':');
  if (line.rfind("frame ", 0) != 0 || colon == std::string::npos)
    return engine::makeError("expected 'frame N: key=value ...'");
  const std::string number = line.substr(6, colon - 6);
  int n = -1;
  if (!parseInt(number, n) || n < 0) return engine::makeError(fmt::format("'{}' is not a frame number", number));
  frame = std::uint64_t(n);
  rest = line.substr(colon + 1);
  return {};
}

}  // namespace

engine::Expected<Script> parseScript(std::string_view text, const std::string& name) {
  Script script;
  script.name = name;
  TuningState scratch;
  std::istringstream lines{std::string(text)};
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    const std::string where = fmt::format("{}:{}", name, number);
    line = line.substr(0, line.find('#'));
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    line = line.substr(line.find_first_not_of(" \t"));
    ScriptFrame frame;
    std::string rest;
    ENGINE_TRY(parseFrameLine(line, frame.frame, rest).withContext(where));
    if (!script.frames.empty() && frame.frame < script.frames.back().frame)
      return engine::makeError(
          fmt::format("{}: frame {} comes after frame {} (frames must not decrease)", where, frame.frame,
                      script.frames.back().frame));
    std::istringstream words(rest);
    for (std::string word; words >> word;) {
      const std::size_t eq = word.find('=');
      frame.commands.push_back({word.substr(0, eq), eq == std::string::npos ? "" : word.substr(eq + 1), number});
    }
    if (frame.commands.empty()) return engine::makeError(where + ": no commands after 'frame N:'");
    // Settings against `scratch`, the tuning the script has built so far, so that ranges are
    // checked when the file is read, not halfway through a run.
    for (auto c = frame.commands.cbegin(); c != frame.commands.cend();) {
      if (isTuning(*c)) {
        const auto end = settingsRun(c, frame.commands.cend());
        ENGINE_TRY(applySettings(c, end, scratch).withContext(where));
        c = end;
      } else {
        ENGINE_TRY(checkAction(*c++).withContext(where));
      }
    }
    script.frames.push_back(std::move(frame));
  }
  return script;
}

engine::Expected<Script> loadScript(const std::filesystem::path& file) {
  ENGINE_TRY_ASSIGN(std::string text, engine::readTextFile(file));
  return parseScript(text, file.string());
}

namespace {

// shader-dir=PATH: the engine loads SPIR-V from PATH from now on, as if the program had been
// started with HSDF_SHADER_DIR=PATH (engine/gpu/pipeline.h); a test points a reload at a copy of
// the build's shaders that it broke, without touching the build or the sources.
Status useShaderDirectory(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_directory(path, ec)) return engine::makeError(fmt::format("shader-dir '{}' is not a directory", path));
  if (setenv("HSDF_SHADER_DIR", path.c_str(), 1) != 0) return engine::makeError("shader-dir: cannot set HSDF_SHADER_DIR");
  engine::log::info("shader-dir: SPIR-V is loaded from {} from now on", path);
  return {};
}

// A run of settings: checked together, then against what the viewer's scene can draw.
Status runSettings(std::vector<ScriptCommand>::const_iterator begin, std::vector<ScriptCommand>::const_iterator end,
                   Viewer& viewer) {
  TuningState tuning = viewer.tuning();
  ENGINE_TRY(applySettings(begin, end, tuning));
  ENGINE_TRY(viewer.checkTuning(tuning));
  viewer.setTuning(tuning);
  return {};
}

Status runAction(const ScriptCommand& c, Viewer& viewer) {
  bool flag = false;
  int view = 0;
  if (c.key == "wait-bake") {
    if (Status baked = viewer.waitForBake(); !baked) engine::log::warn("{}", baked.error().message);
  } else if (c.key == "cancel-bake") {
    viewer.cancelBake();
  } else if (c.key == "reload-shaders") {
    viewer.reloadShaders();  // the result is logged and in the report; a failure is not an error here
    engine::log::info("reload-shaders: panel report: {}", viewer.shaderReloadReport());
  } else if (c.key == "shader-dir") {
    ENGINE_TRY(useShaderDirectory(c.value));
  } else if (c.key == "present-fault") {
    // The engine's fault injection (vk_check.h): the driver presents, the swapchain hears the result.
    engine::gpu::injectFault({"vkQueuePresentKHR", *presentFault(c.value)});
  } else if (c.key == "fail-frame") {
    // After every feature recorded (none can catch it): the renderer drops the frame's commands
    // and, with a window, presents the last finished frame again. The next checked
    // vkEndCommandBuffer is the frame's on a frame that uploads nothing (no new field).
    engine::gpu::injectFault({"vkEndCommandBuffer", VK_ERROR_OUT_OF_DEVICE_MEMORY});
  } else if (c.key == "wait-size") {
    ENGINE_TRY(viewer.waitForWindowSize());
  } else if (c.key == "minimize" || c.key == "restore") {
    ENGINE_TRY(viewer.setMinimized(c.key == "minimize"));
  } else if (c.key == "rebuild-shaders") {
    viewer.rebuildAndReloadShaders();
    engine::log::info("rebuild-shaders: {}", viewer.shaderReloadReport());
  } else if (c.key == "screenshot") {
    viewer.requestScreenshot(c.value);
  } else if (c.key == "size") {
    ENGINE_TRY_ASSIGN(const ImageSize size, parseWindowSize(c.value));
    viewer.resize(size.width, size.height);
  } else if (c.key == "panel" && parseOnOff(c.value, flag)) {
    viewer.setUiVisible(flag);
  } else if (c.key == "vsync" && parseOnOff(c.value, flag)) {
    ENGINE_TRY(viewer.setVsync(flag));
  } else if (c.key == "fullscreen" && parseOnOff(c.value, flag)) {
    viewer.setFullscreen(flag);
  } else if (c.key == "view" && parseInt(c.value, view)) {
    viewer.setCameraMode(CameraMode::Orbit);
    viewer.setOrbitView(view);
  } else if (c.key == "camera") {
    viewer.setCameraMode(c.value == "fly" ? CameraMode::Fly : CameraMode::Orbit);
  } else if (c.key == "scene-camera") {
    ENGINE_TRY(viewer.lookThroughSceneCamera(c.value));
  } else if (c.key == "save-settings") {
    ENGINE_TRY(saveTuning(c.value, viewer.tuning()));
  } else if (c.key == "load-settings") {
    ENGINE_TRY_ASSIGN(TuningState loaded, loadTuning(c.value, viewer.tuning()));
    ENGINE_TRY(viewer.checkTuning(loaded).withContext(c.value));
    viewer.setTuning(loaded);
  }
  return {};
}

}  // namespace

Status runScriptFrame(const Script& script, const ScriptFrame& frame, Viewer& viewer) {
  for (auto c = frame.commands.cbegin(); c != frame.commands.cend();) {
    const auto end = isTuning(*c) ? settingsRun(c, frame.commands.cend()) : c + 1;
    for (auto logged = c; logged != end; ++logged)
      engine::log::info("script frame {}: {}{}{}", frame.frame, logged->key, logged->value.empty() ? "" : "=",
                        logged->value);
    Status ran = isTuning(*c) ? runSettings(c, end, viewer) : runAction(*c, viewer);
    ENGINE_TRY(std::move(ran).withContext(fmt::format("{}:{}", script.name, c->line)));
    c = end;
  }
  return {};
}

}  // namespace samples
