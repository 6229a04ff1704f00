// scene_runner: renders a glTF scene (by default the bundled Stanford bunny) in a window, or
// headless into a PNG. `scene_runner --help` lists the options.
#include <cstdio>
#include <exception>
#include <new>

#include "runner.h"
#include "runner_options.h"

int main(int argc, char** argv) {
  const runner::ParseResult parsed = runner::parseOptions(argc, argv);
  if (!parsed.options) {
    std::fprintf(parsed.exitCode == 0 ? stdout : stderr, "%s\n", parsed.message.c_str());
    return parsed.exitCode;
  }
  try {
    const engine::Status status = runner::run(*parsed.options);
    if (!status.ok()) {
      std::fprintf(stderr, "scene_runner: error: %s\n", status.error().message.c_str());
      return 1;
    }
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "scene_runner: error: out of memory (a smaller --resolution or --size, or --fp16, needs "
                         "less; --bake-budget-mib refuses bakes past a limit before they start)\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scene_runner: fatal: %s\n", e.what());
    return 1;
  }
  return 0;
}
