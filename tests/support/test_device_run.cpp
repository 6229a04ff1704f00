// hsdf_test_device_run PROGRAM [ARGS...]: runs PROGRAM on the device HSDF_TEST_DEVICE names.
// Every ctest that runs a program which creates a Vulkan device (scene_runner, perf_capture, the
// Xvfb scripts, the cmake -P scripts, the consumer project) is started through this launcher. It
// maps HSDF_TEST_DEVICE (gpu|lavapipe|auto, unset = lavapipe) with the same code as the in-process
// test contexts (test_device.h) and exports the result as HSDF_DEVICE, which the engine applies to
// every context left at DevicePreference::Auto -- the programs' default `--device auto` --, in this
// process's children included (a script's scene_runner, the consumer's torus_frame). The variable
// is read when the test runs, not when the build is configured, so one build serves every device.
// An unknown value ends the test here with a message naming the variable and the value.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "engine/gpu/device_names.h"
#include "test_device.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: hsdf_test_device_run PROGRAM [ARGS...]\n");
    return 2;
  }
  const auto preference = hsdftest::testDevicePreference();
  if (!preference) {
    std::fprintf(stderr, "hsdf_test_device_run: %s\n", preference.error().message.c_str());
    return 2;
  }
  const std::string device(engine::gpu::deviceName(*preference));
  if (setenv("HSDF_DEVICE", device.c_str(), 1) != 0) {
    std::fprintf(stderr, "hsdf_test_device_run: cannot set HSDF_DEVICE: %s\n", std::strerror(errno));
    return 2;
  }
  std::fprintf(stderr, "hsdf_test_device_run: HSDF_DEVICE=%s from %s\n", device.c_str(),
               hsdftest::describeTestDevice().c_str());
  std::fflush(stderr);
  execvp(argv[1], argv + 1);
  std::fprintf(stderr, "hsdf_test_device_run: cannot run '%s': %s\n", argv[1], std::strerror(errno));
  return 127;
}
