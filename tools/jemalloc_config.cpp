// SPDX-License-Identifier: MIT
// jemalloc's settings, compiled into the programs (jemalloc reads this symbol when it starts).
//
// The meshing stages allocate and free tens of megabytes at a time (sorted face lists, hex
// arrays, solver vectors). glibc's malloc hands such blocks back to the kernel when they are
// freed and gets fresh ones for the next, and every 4 KB page of fresh memory is a page
// fault, which adds up to a noticeable share of a run. jemalloc keeps freed memory for
// reuse, and with "thp:always" backs its blocks with 2 MB transparent huge pages (where the
// kernel allows them), 512 times fewer faults.
//
// One arena for all threads ("narenas:1"): with an arena per thread, a thread that could not
// get memory for its new arena (under ulimit -v) crashed inside jemalloc instead of failing the
// allocation; the pipeline's threads are two and allocate little, and the time is the same.
extern "C" {
extern const char* malloc_conf;
const char* malloc_conf = "thp:always,narenas:1";
}
