#pragma once
// Large vectors (solves with a block of right-hand sides, per-step loads) are
// allocated and freed every step. glibc gives blocks above its mmap threshold
// back to the kernel at once, so each new one costs a page fault per 4 KiB;
// on virtual machines that fault is slow (measured here: the 16-column partial
// solves of the contact set-up took 2-3x longer, 20 ms of 30 in page faults).
// A program calls this first thing in main(): freed memory then stays with the
// process and is reused. The peak resident memory is unchanged (it is a maximum).
namespace vpc {

void keep_freed_memory();

}  // namespace vpc
