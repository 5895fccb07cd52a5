#pragma once
/// \file
/// Allocator settings of the command-line program (docs/benchmarks.md "Allocator").

namespace stcweave::cli {

/// Keeps the memory freed by one stage for the next: with glibc, every block comes from the
/// heap rather than from a mapping of its own, the heap is not trimmed below 2 GiB, and it
/// grows by at least 256 MiB at a time. Without this, every stage's large vectors are
/// mapped, touched page by page and unmapped again: on the 205,379-hex box a quarter of the
/// run was page faults. Does nothing when the user tunes glibc's malloc (`GLIBC_TUNABLES` with
/// `glibc.malloc`) or on other C libraries. Outputs do not depend on it.
void tune_allocator();

}  // namespace stcweave::cli
