#include "f2c/util/text.h"

#include <charconv>
#include <cmath>
#include <sstream>

#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {

std::vector<TextLine> ReadDataLines(const std::filesystem::path& path) {
  const std::string content = ReadFileToString(path);
  std::vector<TextLine> lines;
  std::istringstream in(content);
  std::string text;
  int number = 0;
  while (std::getline(in, text)) {
    ++number;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    // The same whitespace as SplitWhitespace (isspace), so a kept line always has a token.
    const size_t first = text.find_first_not_of(" \t\r\n\v\f");
    if (first == std::string::npos || text[first] == '#') continue;
    lines.push_back({number, text});
  }
  return lines;
}

std::vector<std::string> SplitWhitespace(std::string_view text) {
  std::vector<std::string> tokens;
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    size_t j = i;
    while (j < text.size() && !std::isspace(static_cast<unsigned char>(text[j]))) ++j;
    if (j > i) tokens.emplace_back(text.substr(i, j - i));
    i = j;
  }
  return tokens;
}

bool ParseDouble(std::string_view token, double* value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), *value);
  return ec == std::errc() && end == token.data() + token.size() && std::isfinite(*value);
}

bool ParseInt(std::string_view token, long* value) {
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), *value);
  return ec == std::errc() && end == token.data() + token.size();
}

std::vector<double> ParseDoublesOrThrow(const std::vector<std::string>& tokens, size_t begin,
                                        const std::filesystem::path& path, int line, const std::string& expected) {
  std::vector<double> values;
  for (size_t i = begin; i < tokens.size(); ++i) {
    double v = 0;
    if (!ParseDouble(tokens[i], &v)) {
      ThrowInputError(path, line, "'" + tokens[i] + "' is not a finite number; expected " + expected);
    }
    values.push_back(v);
  }
  return values;
}

std::vector<double> ReadNumberFile(const std::filesystem::path& path, size_t count, const std::string& what) {
  std::vector<double> numbers;
  for (const TextLine& line : ReadDataLines(path)) {
    const auto values = ParseDoublesOrThrow(SplitWhitespace(line.text), 0, path, line.number, what);
    numbers.insert(numbers.end(), values.begin(), values.end());
  }
  if (numbers.size() != count) {
    ThrowInputError(
        path, "expected " + what + " (" + std::to_string(count) + " numbers), got " + std::to_string(numbers.size()));
  }
  return numbers;
}

}  // namespace f2c
