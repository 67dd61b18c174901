// SPDX-License-Identifier: MIT
#include <dthex/pipeline/memory_budget.h>

#include <dthex/mesh/types.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <sys/resource.h>
#include <unistd.h>

namespace dthex {

namespace {

//! MemAvailable + SwapFree in bytes, or 0 when /proc/meminfo cannot be read.
uint64_t meminfo_available() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  uint64_t kb = 0, available = 0, swap_free = 0;
  std::string unit;
  bool found = false;
  while (in >> key >> kb) {
    std::getline(in, unit);
    if (key == "MemAvailable:") {
      available = kb * 1024;
      found = true;
    } else if (key == "SwapFree:") {
      swap_free = kb * 1024;
    }
  }
  return found ? available + swap_free : 0;
}

// Bytes as a person reads them: MB below a gigabyte (under a tight ulimit -v the message said
// "needs about 0.0 GB of memory, but only 0.0 GB are available"), GB from there on.
std::string memory_text(uint64_t bytes) {
  char text[32];
  if (bytes < uint64_t(1000000000))
    std::snprintf(text, sizeof text, "%.0f MB", double(bytes) / 1e6);
  else
    std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / 1e9);
  return text;
}

}  // namespace

// GCC says __SANITIZE_ADDRESS__, clang (the sanitizer build's) __has_feature.
bool built_with_address_sanitizer() {
#if defined(__SANITIZE_ADDRESS__)
  return true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  return true;
#else
  return false;
#endif
#else
  return false;
#endif
}

uint64_t virtual_size_bytes() {
  std::FILE* status = std::fopen("/proc/self/status", "r");
  if (!status) return 0;
  char line[256];
  unsigned long long kb = 0;
  while (std::fgets(line, sizeof line, status))
    if (std::sscanf(line, "VmSize: %llu kB", &kb) == 1) break;
  std::fclose(status);
  return uint64_t(kb) * 1024;
}

uint64_t available_memory_bytes() {
  uint64_t available = meminfo_available();
  if (available == 0) {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page_size = ::sysconf(_SC_PAGESIZE);
    available = pages > 0 && page_size > 0 ? uint64_t(pages) * uint64_t(page_size) : UINT64_MAX;
  }
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    const uint64_t cap = uint64_t(limit.rlim_cur), used = virtual_size_bytes();
    available = std::min<uint64_t>(available, cap > used ? cap - used : 0);
  }
  return available;
}

uint64_t pipeline_peak_bytes(uint64_t triangles) {
  return kPipelineFixedBytes + kPipelineBytesPerInputTriangle * triangles;
}

void check_memory_budget(const std::string& name, const std::string& what, uint64_t bytes_needed) {
  const uint64_t available = available_memory_bytes();
  if (bytes_needed <= available) return;
  throw InputError(name + ": " + what + " needs about " + memory_text(bytes_needed) + " of memory, but only " +
                   memory_text(available) + " are available");
}

}  // namespace dthex
