#include "f2c/util/fields.h"

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

}  // namespace f2c
