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

//! Rough peak memory of the whole pipeline per input triangle (verification, BVH,
//! coarsening's OpenMesh copy and queues, projection). It is set below the measured peaks,
//! small inputs (where the hex mesh dominates) and large ones (where the input dominates)
//! alike, so only inputs that surely cannot fit are refused.
constexpr uint64_t kPipelineBytesPerInputTriangle = 512;

//! Throws InputError "<name>: <what> needs about X GB of memory, but only Y GB are
//! available" when bytes_needed exceeds available_memory_bytes().
void check_memory_budget(const std::string& name, const std::string& what, uint64_t bytes_needed);

}  // namespace dthex
