#pragma once
// This process's memory as the operating system counts it (Linux: /proc/self/status), for the
// set-up's table of where the memory goes (summary.json "memory_bytes", docs/parallel.md).

namespace vpc {

struct ProcessMemory {
  double resident = 0;  // VmRSS: resident now (bytes)
  double peak = 0;      // VmHWM: the largest resident size so far (bytes)
};

/// Zeros where the system does not say (no /proc).
ProcessMemory process_memory();

}  // namespace vpc
