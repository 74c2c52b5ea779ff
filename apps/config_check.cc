#include "apps/config_check.h"

#include <fmt/format.h>

#include <fstream>
#include <map>
#include <string>

#include "f2c/util/error.h"

namespace f2c::app {
namespace {

std::string Trim(const std::string& text) {
  const size_t begin = text.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return {};
  return text.substr(begin, text.find_last_not_of(" \t\r") - begin + 1);
}

// Whether `value` closes what it opens: a quoted string its quote, a list its bracket.
// A comment after the value ("x = 1  # why") is allowed outside quotes.
const char* Unclosed(const std::string& value) {
  const char open = value[0];
  if (open == '"' || open == '\'') {
    for (size_t i = 1; i < value.size(); ++i) {
      if (open == '"' && value[i] == '\\') {
        ++i;
      } else if (value[i] == open) {
        const std::string rest = Trim(value.substr(i + 1));
        return rest.empty() || rest[0] == '#' || rest[0] == ';' ? nullptr : "text after the closing quote";
      }
    }
    return "a string that is never closed";
  }
  if (open == '[') {
    size_t depth = 0;
    char quote = 0;
    for (char c : value) {
      if (quote != 0) {
        if (c == quote) quote = 0;
      } else if (c == '"' || c == '\'') {
        quote = c;
      } else if (c == '[') {
        ++depth;
      } else if (c == ']' && --depth == 0) {
        return nullptr;
      }
    }
    return "a list that is never closed";
  }
  return nullptr;
}

}  // namespace

void CheckConfigFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return;
  std::string section;
  std::map<std::string, int> line_of_key;
  int number = 0;
  for (std::string raw; std::getline(in, raw);) {
    ++number;
    const std::string line = Trim(raw);
    if (line.empty() || line[0] == '#' || line[0] == ';') continue;
    if (line[0] == '[') {
      const size_t close = line.find(']');
      if (close != std::string::npos)
        section = Trim(line.substr(line.rfind('[', close) + 1, close - line.rfind('[', close) - 1));
      continue;
    }
    const size_t eq = line.find('=');
    if (eq == std::string::npos) continue;  // CLI11 says what it makes of it
    const std::string key = Trim(line.substr(0, eq));
    const std::string value = Trim(line.substr(eq + 1));
    const std::string full = section.empty() ? key : section + "." + key;
    if (value.empty()) {
      ThrowInputError(path, number, fmt::format("'{}' has no value (\"\" for empty text)", key));
    }
    if (const char* problem = Unclosed(value)) ThrowInputError(path, number, fmt::format("'{}': {}", key, problem));
    const auto [first, fresh] = line_of_key.emplace(full, number);
    if (!fresh) {
      ThrowInputError(path, number, fmt::format("'{}' given twice (first on line {})", full, first->second));
    }
  }
}

}  // namespace f2c::app
