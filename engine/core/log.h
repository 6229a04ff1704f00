#pragma once
// Minimal levelled logging to stderr. A sink can be installed (tests capture messages).
#include <fmt/format.h>
#include <functional>
#include <string>
#include <string_view>

namespace engine::log {

enum class Level { Debug, Info, Warning, Error };

using Sink = std::function<void(Level, std::string_view)>;

void setSink(Sink sink);          // empty sink restores the default stderr sink
void setMinLevel(Level level);    // messages below are dropped (default Info; HSDF_LOG=debug)
void write(Level level, std::string_view message);

template <class... Args>
void debug(fmt::format_string<Args...> pattern, Args&&... args) {
  write(Level::Debug, fmt::format(pattern, std::forward<Args>(args)...));
}
template <class... Args>
void info(fmt::format_string<Args...> pattern, Args&&... args) {
  write(Level::Info, fmt::format(pattern, std::forward<Args>(args)...));
}
template <class... Args>
void warn(fmt::format_string<Args...> pattern, Args&&... args) {
  write(Level::Warning, fmt::format(pattern, std::forward<Args>(args)...));
}
template <class... Args>
void error(fmt::format_string<Args...> pattern, Args&&... args) {
  write(Level::Error, fmt::format(pattern, std::forward<Args>(args)...));
}

}  // namespace engine::log
