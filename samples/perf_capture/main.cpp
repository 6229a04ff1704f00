// perf_capture: the paper's results table on the bunny (or a glTF scene / an analytic shape) with
// quality and work metrics, from one command. See capture_options.h and README "Perf capture".
#include <cstdio>
#include <exception>
#include <new>

#include "capture.h"

int main(int argc, char** argv) {
  const capture::ParseResult parsed = capture::parseOptions(argc, argv);
  if (!parsed.options) {
    std::fprintf(parsed.exitCode ? stderr : stdout, "%s\n", parsed.message.c_str());
    return parsed.exitCode;
  }
  int failedRows = 0;
  engine::Status status;
  try {
    status = capture::run(*parsed.options, failedRows);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "perf_capture: error: out of memory (fewer or smaller --resolutions, or a smaller --size, "
                         "need less)\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "perf_capture: fatal: %s\n", e.what());
    return 1;
  }
  if (!status.ok()) {
    std::fprintf(stderr, "perf_capture: error: %s\n", status.error().message.c_str());
    return 1;
  }
  if (failedRows > 0) {
    std::fprintf(stderr, "perf_capture: %d row(s) failed to render (see results.md)\n", failedRows);
    return 1;
  }
  return 0;
}
