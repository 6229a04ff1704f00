#pragma once
// A one-line terminal progress bar ("baking [#########-----------]  45%") redrawn in place.
#include <cstdio>
#include <string>

namespace hsdf::tools {

class ProgressBar {
 public:
  ProgressBar(std::string label, std::FILE* out) : label_(std::move(label)), out_(out) {}
  // Redraws when the whole percentage changes; always returns true (never cancels).
  bool update(float fraction);
  // Draws 100% and ends the line.
  void finish();

 private:
  void draw(int percent);
  std::string label_;
  std::FILE* out_;
  int shown_ = -1;
};

}  // namespace hsdf::tools
