#include "engine/core/log.h"

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>

namespace engine::log {
namespace {

struct State {
  std::mutex mutex;
  Sink sink;
  Level minLevel = Level::Info;
};

State& state() {
  static State* s = [] {
    auto* created = new State();  // never destroyed: logging may happen during static teardown
    if (const char* env = std::getenv("HSDF_LOG"); env && std::string(env) == "debug")
      created->minLevel = Level::Debug;
    return created;
  }();
  return *s;
}

const char* levelName(Level level) {
  switch (level) {
    case Level::Debug: return "debug";
    case Level::Info: return "info";
    case Level::Warning: return "warning";
    case Level::Error: return "error";
  }
  return "?";
}

}  // namespace

void setSink(Sink sink) {
  std::lock_guard lock(state().mutex);
  state().sink = std::move(sink);
}

void setMinLevel(Level level) {
  std::lock_guard lock(state().mutex);
  state().minLevel = level;
}

void write(Level level, std::string_view message) {
  State& s = state();
  std::lock_guard lock(s.mutex);
  if (level < s.minLevel) return;
  if (s.sink) {
    s.sink(level, message);
    return;
  }
  std::fprintf(stderr, "[%s] %.*s\n", levelName(level), static_cast<int>(message.size()), message.data());
}

}  // namespace engine::log
