#pragma once
// Strict parsing of the small text formats datasets use: a line is split on white space
// and every number must parse completely (so "1.0x" or "nan" is an error, not a 1).

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace f2c {

struct TextLine {
  int number = 0;    // 1-based line number in the file
  std::string text;  // without the end-of-line
};

// Lines of a text file, with '\r' stripped; blank lines and lines starting with '#' are
// dropped. InputError when the file cannot be read.
std::vector<TextLine> ReadDataLines(const std::filesystem::path& path);

std::vector<std::string> SplitWhitespace(std::string_view text);

// Parses a finite double; false if `token` is not entirely a finite number.
bool ParseDouble(std::string_view token, double* value);
bool ParseInt(std::string_view token, long* value);

// Parses every token of `tokens[begin..]` as a finite double, or raises InputError at
// path:line saying what was expected.
std::vector<double> ParseDoublesOrThrow(const std::vector<std::string>& tokens, size_t begin,
                                        const std::filesystem::path& path, int line, const std::string& expected);

// Reads a file of exactly `count` numbers in any line layout (a matrix file), or raises
// InputError "<path>: expected <what> (<count> numbers), got N" / a bad-token error.
std::vector<double> ReadNumberFile(const std::filesystem::path& path, size_t count, const std::string& what);

}  // namespace f2c
