#pragma once
// Sets one field of an options struct by its flag's long name, from its one field list
// (f2c/util/fields.h): how an embedder that passes options by name (the Python module's
// keyword arguments) reaches the same fields as the command line. A bool flag "--x,!--no-x"
// answers to "x" (and "no-x", negated), "--x=on|off" to "x"; enums take their names. Nested
// structs' fields are found under their own names; internal copies (with_flags false) are not.
// Ranges are left to the struct's Check(), as on the command line.

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "f2c/util/error.h"
#include "f2c/util/fields.h"

namespace f2c {

using FieldValue = std::variant<bool, int64_t, double, std::string>;

namespace internal {

// The long names a flag spec answers to ("--x,!--no-x" -> {x, false}, {no-x, true}).
struct FlagName {
  std::string name;
  bool negated = false;
};
std::vector<FlagName> FlagNames(const char* flag);

class FieldSetter {
 public:
  FieldSetter(std::string_view name, const FieldValue& value) : name_(name), value_(value) {}
  void Group(const char*) {}
  template <class T>
  void Field(T& field, const char*, const char* flag, const Bounds&, const char*) {
    if (found_ || flag == nullptr || *flag == '\0') return;
    for (const FlagName& f : FlagNames(flag)) {
      if (f.name != name_) continue;
      found_ = true;
      Set(field, f.negated);
      return;
    }
  }
  template <class S>
  void Nested(S& options, const char*, bool with_flags = true) {
    if (!found_ && with_flags) options.Fields(*this);
  }
  bool found() const { return found_; }

 private:
  [[noreturn]] void Wrong(const char* wanted) const;
  template <class T>
  void Set(T& field, bool negated) {
    if constexpr (std::is_same_v<T, bool>) {
      if (!std::holds_alternative<bool>(value_)) Wrong("True or False");
      field = std::get<bool>(value_) != negated;
    } else if constexpr (std::is_enum_v<T>) {
      if (!std::holds_alternative<std::string>(value_)) Wrong(("one of " + NamesOf<T>()).c_str());
      field = FromName<T>(std::get<std::string>(value_), "--" + std::string(name_));
    } else if constexpr (std::is_integral_v<T>) {
      if (!std::holds_alternative<int64_t>(value_)) Wrong("a whole number");
      const int64_t v = std::get<int64_t>(value_);
      if constexpr (std::is_unsigned_v<T>) {
        if (v < 0) Wrong("a whole number >= 0");
      } else {
        if (v < static_cast<int64_t>(std::numeric_limits<T>::min()) ||
            v > static_cast<int64_t>(std::numeric_limits<T>::max())) {
          Wrong("a whole number within the option's type");
        }
      }
      field = static_cast<T>(v);
    } else if constexpr (std::is_floating_point_v<T>) {
      if (std::holds_alternative<double>(value_)) {
        field = static_cast<T>(std::get<double>(value_));
      } else if (std::holds_alternative<int64_t>(value_)) {
        field = static_cast<T>(std::get<int64_t>(value_));
      } else {
        Wrong("a number");
      }
    } else if constexpr (std::is_constructible_v<T, std::string>) {
      if (!std::holds_alternative<std::string>(value_)) Wrong("a string");
      field = T(std::get<std::string>(value_));
    } else {
      Wrong("a value of a type this interface does not set");
    }
  }

  std::string_view name_;
  const FieldValue& value_;
  bool found_ = false;
};

}  // namespace internal

// Sets the field of `options` whose flag's long name (without "--") is `name`; false when no
// field has it. InputError naming it when `value` is of the wrong kind (a string for a
// number, an unknown enum name, a fraction for a whole number).
template <class S>
bool SetFieldByFlag(S& options, std::string_view name, const FieldValue& value) {
  internal::FieldSetter setter(name, value);
  options.Fields(setter);
  return setter.found();
}

}  // namespace f2c
