#pragma once
// Shared by the CLI tests: run the fine2coarse binary as a user would, and small inputs.

#include <cstdint>
#include <filesystem>
#include <string>

namespace f2c::cli_test {

struct Result {
  int code = -1;
  std::string output;  // stdout and stderr
};

// `shell_tail` follows the command line as is (redirections of its own).
Result RunCli(const std::string& args, const std::string& shell_tail = " 2>&1");

// zlib's CRC-32 (PNG chunks), bit by bit: a test needs only a few bytes of it.
uint32_t Crc32ForTest(const std::string& bytes);

// A real data set in ../shared/data (may be absent: tests skip).
std::filesystem::path Data(const std::string& name);

// n frames of the synthetic room, TUM layout, in a fresh temporary folder.
std::filesystem::path SyntheticTum(const std::string& name, int n);

}  // namespace f2c::cli_test
