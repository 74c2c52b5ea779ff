#pragma once
// Errors. Bad input (files, folders, option values a user typed) raises InputError,
// whose message is one line that names the file and what is wrong; the CLI prints it and
// exits 1. Programmer invariants use F2C_CHECK, which is never expected to fire.

#include <filesystem>
#include <stdexcept>
#include <string>

namespace f2c {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A broken invariant of our own (F2C_CHECK): a bug, never the user's input.
class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

// Throws InputError("<path>: <what>"); an empty path is written "(empty path)".
[[noreturn]] void ThrowInputError(const std::filesystem::path& path, const std::string& what);
// Throws InputError("<path>:<line>: <what>") for an error on a line of a text file.
[[noreturn]] void ThrowInputError(const std::filesystem::path& path, int line, const std::string& what);

[[noreturn]] void CheckFailed(const char* file, int line, const char* condition, const std::string& message);

}  // namespace f2c

#define F2C_CHECK(condition, message)                                              \
  do {                                                                             \
    if (!(condition)) ::f2c::CheckFailed(__FILE__, __LINE__, #condition, message); \
  } while (false)
