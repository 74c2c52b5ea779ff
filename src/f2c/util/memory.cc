#include "f2c/util/memory.h"

#include <fstream>
#include <string>

namespace f2c {
namespace {

int64_t StatusField(const std::string& key) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.compare(0, key.size(), key) == 0) return std::stoll(line.substr(key.size())) * 1024;  // kB
  }
  return 0;
}

}  // namespace

int64_t PeakResidentBytes() { return StatusField("VmHWM:"); }
int64_t ResidentBytes() { return StatusField("VmRSS:"); }

}  // namespace f2c
