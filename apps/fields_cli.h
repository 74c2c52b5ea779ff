#pragma once
// An options struct's command-line flags, from its one field list (f2c/util/fields.h): each
// field with a flag becomes an option with its help and its default shown in --help (and so
// written by --write-config). Bools are flags ("--x,!--no-x") or, spelt "--x=on|off", options
// taking on or off; enums take their names.
// Ranges are not checked here but by the struct's Check() at the stage boundary, so a bad
// value from a --config file gets the same message as one typed.

#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <type_traits>

#include "f2c/util/fields.h"

namespace f2c::app {
namespace internal {

class FieldFlagAdder {
 public:
  explicit FieldFlagAdder(CLI::App* cmd) : cmd_(cmd) {}
  void Group(const char* name) { group_ = name; }
  template <class T>
  void Field(T& value, const char* key, const char* flag, const Bounds&, const char* help) {
    if (flag == nullptr || *flag == '\0') return;
    const std::string spec = flag;
    if constexpr (std::is_same_v<T, bool>) {
      if (spec.ends_with("=on|off")) {  // "--keyframes on": a switch that is on by default
        cmd_->add_option(spec.substr(0, spec.size() - 7), value, help)
            ->transform(CLI::CheckedTransformer(std::map<std::string, bool>{{"on", true}, {"off", false}}))
            ->default_str(value ? "on" : "off")
            ->group(group_);
        return;
      }
      // The default as the flag's own sense: "!--no-x" is set (true) when the field is false,
      // so --write-config writes no-x=false for a field that is true, and reads it back so.
      const bool negated = spec[0] == '!';
      cmd_->add_flag(flag, value, help)->default_str(value != negated ? "true" : "false")->group(group_);
    } else if constexpr (std::is_enum_v<T>) {
      const std::string name = FieldName(flag, key);
      cmd_->add_option_function<std::string>(
              flag, [&value, name](const std::string& text) { value = FromName<T>(text, name); }, help)
          ->default_str(NameOf(value))
          ->group(group_);
    } else if constexpr (std::is_integral_v<T> && std::is_unsigned_v<T>) {
      // CLI11 reads "-1" into an unsigned as 2^64 - 1: parsed here, so that a negative or
      // partial number is bad input naming the flag.
      const std::string name = FieldName(flag, key);
      cmd_->add_option_function<std::string>(
              flag, [&value, name](const std::string& text) { value = ParseUnsigned<T>(text, name); }, help)
          ->default_str(std::to_string(value))
          ->group(group_);
    } else {
      cmd_->add_option(flag, value, help)->capture_default_str()->group(group_);
    }
  }
  template <class S>
  void Nested(S& options, const char*, bool with_flags = true) {
    if (!with_flags) return;           // an internal copy (SIFT loops' RANSAC): the odometry's flags are the ones
    const std::string group = group_;  // a nested struct names its own group
    options.Fields(*this);
    group_ = group;
  }

 private:
  CLI::App* cmd_;
  std::string group_ = "Options";
};

}  // namespace internal

// Adds every flag of `options` to `cmd`; `options` must outlive the parse.
template <class S>
void AddFieldFlags(CLI::App* cmd, S* options) {
  internal::FieldFlagAdder adder(cmd);
  options->Fields(adder);
}

}  // namespace f2c::app
