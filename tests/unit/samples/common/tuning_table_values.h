#pragma once
// Values for walking the tuning table (tuning_fields.h) in tests: each derived from a row alone, so
// that a new row is tested by the walks without an edit to them.
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "tuning_fields.h"

namespace samples::testing {

inline bool isFloatField(const TuningField& field) { return std::holds_alternative<float TuningState::*>(field.member); }

inline std::string numberText(const TuningField& field, double value) {
  return isFloatField(field) ? fmt::format("{}", float(value)) : fmt::format("{}", std::llround(value));
}

// A value of `field` other than its value in `base`, as its command-line option takes it: another of
// a number's choices or the point 3/4 into its range, the other bool, the first other name, two
// node names.
inline std::string otherValueText(const TuningField& field, const TuningState& base) {
  const std::string current = tuningValueText(field, base);
  switch (tuningKind(field)) {
    case TuningKind::Number:
      for (const std::uint32_t choice : field.choices)
        if (std::to_string(choice) != current) return std::to_string(choice);
      return numberText(field, field.range.min + 0.75 * (field.range.max - field.range.min));
    case TuningKind::Bool: return current == "true" ? "false" : "true";
    case TuningKind::Name:
      for (const std::string& name : tuningNames(field))
        if (name != current) return name;
      return current;
    case TuningKind::Names: break;
  }
  return "node a,node b";
}

// Numbers just outside a number's range: below and above it (an int by one, a float by half its
// bound, or by one below a bound of 0, then twice it).
inline std::string belowRangeText(const TuningField& field) {
  const double min = field.range.min;
  return numberText(field, isFloatField(field) && min > 0.0 ? min * 0.5 : min - 1.0);
}
inline std::string aboveRangeText(const TuningField& field) {
  return numberText(field, isFloatField(field) ? field.range.max * 2.0 : field.range.max + 1.0);
}

// The state every walk starts from: the compared method of cells, whose K range is the widest, so
// that any compare_resolution of the table's range is drawable.
inline TuningState walkBase() {
  TuningState base;
  base.compareMethod = hsdf::RenderMethod::Cells;
  return base;
}

}  // namespace samples::testing
