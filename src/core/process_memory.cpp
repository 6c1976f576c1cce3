#include "core/process_memory.hpp"

#include <fstream>
#include <string>

namespace vpc {

ProcessMemory process_memory() {
  ProcessMemory m;
  std::ifstream status("/proc/self/status");
  std::string key;
  double kib = 0;
  std::string unit;
  while (status >> key) {
    if (key == "VmRSS:" || key == "VmHWM:") {
      if (!(status >> kib >> unit)) break;
      (key == "VmRSS:" ? m.resident : m.peak) = kib * 1024;
    }
    status.ignore(1 << 20, '\n');
  }
  return m;
}

}  // namespace vpc
