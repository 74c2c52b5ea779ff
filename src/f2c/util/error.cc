#include "f2c/util/error.h"

#include <fmt/format.h>

namespace f2c {

void ThrowInputError(const std::filesystem::path& path, const std::string& what) {
  // An empty name (an option given as "") is said in words: "error: : ..." names nothing.
  throw InputError(fmt::format("{}: {}", path.empty() ? std::string("(empty path)") : path.string(), what));
}

void ThrowInputError(const std::filesystem::path& path, int line, const std::string& what) {
  throw InputError(fmt::format("{}:{}: {}", path.string(), line, what));
}

void CheckFailed(const char* file, int line, const char* condition, const std::string& message) {
  throw InternalError(fmt::format("{}:{}: check '{}' failed: {}", file, line, condition, message));
}

}  // namespace f2c
