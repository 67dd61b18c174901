// SPDX-License-Identifier: MIT
// Refusing an input up front when meshing it would need more memory than the machine
// has: better a clear message in a second than an out-of-memory kill after an hour.
#pragma once

#include <cstdint>
#include <string>

namespace dthex {

//! Bytes this process can still hope to get: the smaller of the memory the kernel
//! reports available (MemAvailable + SwapFree in /proc/meminfo, or physical pages by
//! sysconf where that file is missing) and what the address-space limit (RLIMIT_AS,
//! e.g. ulimit -v) leaves above the current virtual size.
uint64_t available_memory_bytes();

//! The process's current virtual size (VmSize in /proc/self/status), 0 if unknown.
uint64_t virtual_size_bytes();

//! The peak memory of the whole pipeline on a closed surface of `triangles` triangles at
//! the default options: kPipelineFixedBytes + kPipelineBytesPerInputTriangle x triangles.
//! The two constants are the least-squares line through the peak resident sets that
//! build/benchmark measures (its peak MB) on the femur Loop-subdivided 1, 2 and 3 times,
//! rounded up; the line is within a few percent of each. The peak is in the coarsening (the
//! input, its tree, and the decimater's copies of it), all in proportion to the input, as is
//! the hex mesh, whose smallest size is the mean input edge. Coarser options need less.
uint64_t pipeline_peak_bytes(uint64_t triangles);
constexpr uint64_t kPipelineFixedBytes = uint64_t(56) << 20;
constexpr uint64_t kPipelineBytesPerInputTriangle = 448;

//! Whether the library was built with AddressSanitizer, which reserves terabytes of address
//! space: an address-space limit (RLIMIT_AS) would stop it, and its shadow memory is not in
//! the model above. A function, not a constant, so that code compiled without the sanitizer
//! (the sanitizer build's test files) gets the library's answer.
bool built_with_address_sanitizer();

//! Throws InputError "<name>: <what> needs about X GB of memory, but only Y GB are
//! available" when bytes_needed exceeds available_memory_bytes().
void check_memory_budget(const std::string& name, const std::string& what, uint64_t bytes_needed);

}  // namespace dthex
