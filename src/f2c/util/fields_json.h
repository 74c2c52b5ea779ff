#pragma once
// An options struct as JSON, from its one field list (f2c/util/fields.h): each field under
// its member name, enums by name, nested structs as objects. run.json and the report record
// the options of every run this way.

#include <nlohmann/json.hpp>
#include <type_traits>

#include "f2c/util/fields.h"

namespace f2c {
namespace internal {

class FieldJsonWriter {
 public:
  explicit FieldJsonWriter(nlohmann::json* out) : out_(out) {}
  void Group(const char*) {}
  template <class T>
  void Field(const T& value, const char* key, const char*, const Bounds&, const char*) {
    if constexpr (std::is_enum_v<T>) {
      (*out_)[key] = NameOf(value);
    } else {
      (*out_)[key] = value;
    }
  }
  template <class S>
  void Nested(const S& options, const char* key, bool = true) {
    nlohmann::json nested = nlohmann::json::object();
    FieldJsonWriter writer(&nested);
    const_cast<S&>(options).Fields(writer);
    (*out_)[key] = std::move(nested);
  }

 private:
  nlohmann::json* out_;
};

}  // namespace internal

template <class S>
nlohmann::json FieldsToJson(const S& options) {
  nlohmann::json out = nlohmann::json::object();
  internal::FieldJsonWriter writer(&out);
  const_cast<S&>(options).Fields(writer);
  return out;
}

}  // namespace f2c
