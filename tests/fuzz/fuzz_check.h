#pragma once
// FUZZ_CHECK(condition): an invariant a fuzz target asserts about an input it accepted. A failed
// check prints what failed and aborts, which libFuzzer and the corpus replay report as a crash.
#include <cstdio>
#include <cstdlib>

#define FUZZ_CHECK(condition)                                                              \
  do {                                                                                     \
    if (!(condition)) {                                                                    \
      std::fprintf(stderr, "FUZZ_CHECK failed: %s (%s:%d)\n", #condition, __FILE__, __LINE__); \
      std::abort();                                                                        \
    }                                                                                      \
  } while (0)
