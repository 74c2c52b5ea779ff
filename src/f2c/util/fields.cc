#include "f2c/util/fields.h"

#include <fmt/format.h>

#include "f2c/util/fields_set.h"

namespace f2c {

bool Bounds::Admits(double value) const {
  if (!std::isfinite(value)) return false;
  if (min_open ? !(value > min) : !(value >= min)) return false;
  return max_open ? value < max : value <= max;
}

std::string Bounds::Describe() const {
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (has_min && has_max) {
    return fmt::format("in {}{}, {}{}", min_open ? "(" : "[", min, max, max_open ? ")" : "]");
  }
  if (has_min) return fmt::format("{} {}", min_open ? ">" : ">=", min);
  if (has_max) return fmt::format("{} {}", max_open ? "<" : "<=", max);
  return "finite";
}

std::string FieldName(const char* flag, const char* key) {
  std::string name = flag ? flag : "";
  name = name.substr(0, name.find_first_of(",="));
  if (!name.empty() && name[0] == '!') name.erase(0, 1);
  return name.empty() ? std::string(key) : name;
}

namespace internal {

std::vector<FlagName> FlagNames(const char* flag) {
  std::vector<FlagName> names;
  std::string spec = flag ? flag : "";
  size_t start = 0;
  while (start <= spec.size()) {
    size_t end = spec.find(',', start);
    if (end == std::string::npos) end = spec.size();
    std::string part = spec.substr(start, end - start);
    part = part.substr(0, part.find('='));  // "--keyframes=on|off"
    FlagName f;
    if (!part.empty() && part[0] == '!') {
      f.negated = true;
      part.erase(0, 1);
    }
    if (part.rfind("--", 0) == 0) {  // long names only ("-q" is not a name)
      f.name = part.substr(2);
      names.push_back(f);
    }
    start = end + 1;
  }
  return names;
}

void FieldSetter::Wrong(const char* wanted) const {
  std::string got;
  if (std::holds_alternative<bool>(value_)) got = std::get<bool>(value_) ? "True" : "False";
  if (std::holds_alternative<int64_t>(value_)) got = std::to_string(std::get<int64_t>(value_));
  if (std::holds_alternative<double>(value_)) got = fmt::format("{}", std::get<double>(value_));
  if (std::holds_alternative<std::string>(value_)) got = "'" + std::get<std::string>(value_) + "'";
  ThrowInputError("--" + std::string(name_), fmt::format("must be {}, got {}", wanted, got));
}

}  // namespace internal

}  // namespace f2c
