#pragma once
// Options declared once (docs/options.md). Every options struct lists its fields in one member
// template, beside their defaults:
//
//   struct WindowOptions {
//     int initial_frames = 8;  // l_0
//     ...
//     template <class V> void Fields(V& v) {
//       v.Group("Refinement: windows (paper 4.2)");
//       F2C_FIELD(v, initial_frames, "--window-frames", AtLeast(2), "l_0, frames in the first windows");
//       F2C_NESTED(v, pairs);  // an options struct of its own, with its own Fields
//     }
//     void Check() const;  // CheckFields(*this), then any rule that ties fields together
//   };
//
// and everything else comes from that list: CheckFields (every number finite and within its
// bounds, the message naming the flag), FieldsToJson (f2c/util/fields_json.h), the command
// line with each flag's help and default (apps/fields_cli.h) and, through it, --write-config.
// A field with no flag ("") is internal: checked and written to JSON, not on the command line.
//
// A visitor V has Group(name), Field(value, key, flag, bounds, help) and Nested(options, key,
// with_flags); with_flags false marks an internal copy of a struct whose flags belong to
// another stage (the SIFT loops' RANSAC, whose flags are the odometry's).

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <type_traits>

#include "f2c/util/error.h"

namespace f2c {

// The values a number may take; every one must also be finite. Bounds are written in the
// error message as the user would write them ("must be >= 2, got 1").
struct Bounds {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;  // min itself is excluded
  bool max_open = false;

  bool Admits(double value) const;
  std::string Describe() const;  // "finite", ">= 2", "> 0", "in (0, 180]"
};

inline Bounds AnyFinite() { return {}; }
inline Bounds AtLeast(double min) { return {.min = min}; }
inline Bounds Positive() { return {.min = 0, .min_open = true}; }
inline Bounds Between(double min, double max) { return {.min = min, .max = max}; }
// (min, max]
inline Bounds AboveUpTo(double min, double max) { return {.min = min, .max = max, .min_open = true}; }

// The name an error message gives a field: its flag's first long name ("--sift-loops" for
// "--sift-loops,!--no-sift-loops"), else its key.
std::string FieldName(const char* flag, const char* key);

// An enum's names, for the command line and JSON: declare next to the enum with
//   F2C_ENUM_NAMES(WindowMode, {{WindowMode::kFrames, "frames"}, {WindowMode::kPath, "path"}})
template <class E>
struct EnumName {
  E value;
  const char* name;
};

#define F2C_ENUM_NAMES(E, ...)                                  \
  inline std::span<const ::f2c::EnumName<E>> EnumNames(E) {     \
    static constexpr ::f2c::EnumName<E> kNames[] = __VA_ARGS__; \
    return kNames;                                              \
  }

template <class E>
const char* NameOf(E value) {
  for (const auto& n : EnumNames(E{})) {
    if (n.value == value) return n.name;
  }
  return "?";
}

// "a, b, c": the names an enum accepts, for help and error messages.
template <class E>
std::string NamesOf() {
  std::string names;
  for (const auto& n : EnumNames(E{})) names += (names.empty() ? "" : ", ") + std::string(n.name);
  return names;
}

// The value named `name`; InputError "<what>: unknown value 'x' (a, b, c)" otherwise.
template <class E>
E FromName(const std::string& name, const std::string& what) {
  for (const auto& n : EnumNames(E{})) {
    if (name == n.name) return n.value;
  }
  ThrowInputError(what, fmt::format("unknown value '{}' ({})", name, NamesOf<E>()));
}

// A whole number >= 0 of type T from `text` (all of it), or InputError naming `what`.
template <class T>
T ParseUnsigned(const std::string& text, const std::string& what) {
  T value{};
  const char* end = text.data() + text.size();
  const auto [at, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc() || at != end) {
    ThrowInputError(what,
                    fmt::format("must be a whole number from 0 to {}, got '{}'", std::numeric_limits<T>::max(), text));
  }
  return value;
}

#define F2C_FIELD(v, member, flag, bounds, help) (v).Field(member, #member, flag, bounds, help)
#define F2C_NESTED(v, member) (v).Nested(member, #member)

namespace internal {

class FieldChecker {
 public:
  void Group(const char*) {}
  template <class T>
  void Field(const T& value, const char* key, const char* flag, const Bounds& bounds, const char*) {
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
      if (!bounds.Admits(static_cast<double>(value))) {
        ThrowInputError(FieldName(flag, key), fmt::format("must be {}, got {}", bounds.Describe(), value));
      }
    }
  }
  template <class S>
  void Nested(const S& options, const char*, bool = true) {
    options.Check();
  }
};

}  // namespace internal

// Every field of `options` within its bounds, and every nested struct's Check(); InputError
// naming the first that is not. Fields() does not change the struct; it is not const only
// so that the one list also serves the visitors that write fields.
template <class S>
void CheckFields(const S& options) {
  internal::FieldChecker checker;
  const_cast<S&>(options).Fields(checker);
}

}  // namespace f2c
