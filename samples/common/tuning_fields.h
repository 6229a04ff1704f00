#pragma once
// The table of tuning settings: each member of TuningState that a user sets is one row, with its
// key (settings files, --script lines), its command-line option, its panel label, its help text
// (the option's --help line and the panel's tooltip), its range and the member it reads and writes.
// The settings files' reader and writer, the scene runner's options and the panel's labels and
// tooltips are made from it, so a new setting is a member of TuningState and a row of the table
// (tuning_fields.cpp), and the ranges the help names are the ranges checked.
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "tuning.h"

namespace samples {

// The member a field reads and writes. Its type is the field's kind: how a file writes it, how the
// command line gives it and how the panel shows it.
using TuningMember =
    std::variant<int TuningState::*, std::uint32_t TuningState::*, float TuningState::*, bool TuningState::*,
                 Method TuningState::*, hsdf::NormalMode TuningState::*, DebugView TuningState::*,
                 AutoSwitch TuningState::*, SplitMode TuningState::*, hsdf::NodeDraw TuningState::*,
                 std::vector<std::string> TuningState::*>;

// What the kinds have in common, for code that walks the table (the tests, the runner's options).
enum class TuningKind {
  Number,  // int, std::uint32_t, float: within TuningField::range
  Bool,    // true or false
  Name,    // one of tuningNames(field): a method, a mode, a view, an auto / on / off switch
  Names,   // a list of names (nodes), comma-separated on the command line
};

// How a bool is given on the command line: --fp16 (sets it), --no-front-to-back (clears it), or
// --cull-cells true|false (a value, for settings whose default is on but that had no --no- form).
enum class BoolOption { Flag, NegatedFlag, Value };

// A range of numbers, as doubles: it holds an int range exactly and a float one as the floats the
// member holds (float(min) is the bound checked).
struct NumberRange {
  double min = 0.0;
  double max = 0.0;
};

struct TuningField {
  const char* key;      // "tile_size"
  const char* option;   // "--tile-size" (for BoolOption::NegatedFlag: "--no-front-to-back")
  const char* label;    // the panel's words for it
  std::string help;     // what it does; tuningHelp adds the range and the default
  TuningMember member;
  NumberRange range{};  // numbers only
  // Numbers: the only values taken, within `range` (tile sizes); empty: every value of the range.
  // A value outside them but in range is refused by validateTuning (its message names the values).
  std::span<const std::uint32_t> choices{};
  bool zeroIsDerived = false;  // numbers: 0 stands for a value derived from others (compare_resolution: 2K)
  bool sdfMethodsOnly = false;  // methods: one of the module's SDF methods, not mesh (compare_method)
  BoolOption boolOption = BoolOption::Value;
};

// Every field, in the order of --help and of the settings files' keys.
std::span<const TuningField> tuningFields();
// The field of a key; nullptr for a key that is not a setting.
const TuningField* findTuningField(std::string_view key);
// The field of a key the caller knows (the panel's controls): a missing key is a programming error,
// reported and aborted on.
const TuningField& tuningField(std::string_view key);

TuningKind tuningKind(const TuningField& field);
// A Name field's names, as the command line gives them (an auto switch: auto, on, off); else empty.
std::vector<std::string> tuningNames(const TuningField& field);
// The field's value in `tuning` as its command-line option takes it ("64", "true", "trilinear",
// "auto", "a,b").
std::string tuningValueText(const TuningField& field, const TuningState& tuning);
// `help` with what the table knows: the range or the values and the default.
std::string tuningHelp(const TuningField& field);
// Sets the field from its command-line text (tuningValueText's form): the number, bool or names
// checked against the field's kind and range, not against the other settings (validateTuning).
engine::Status setTuningFromText(const TuningField& field, std::string_view text, TuningState& tuning);
// A number within the field's range and choices, else a message naming the option ("--padding 17 is
// outside 0..16"): validateTuning's check of every number, whoever wrote it (the panel, a program).
engine::Status checkTuningRange(const TuningField& field, const TuningState& tuning);
// Whether `a` and `b` hold the same value of the field.
bool sameTuningValue(const TuningField& field, const TuningState& a, const TuningState& b);

}  // namespace samples
