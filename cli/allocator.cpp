#include "allocator.hpp"

#include <cstdlib>
#include <string_view>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace stcweave::cli {

void tune_allocator() {
#if defined(__GLIBC__)
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables != nullptr &&
      std::string_view(tunables).find("glibc.malloc") != std::string_view::npos)
    return;
  constexpr int kMiB = 1024 * 1024;
  mallopt(M_MMAP_MAX, 0);  // no block gets its own mapping (glibc still maps if brk fails)
  mallopt(M_TRIM_THRESHOLD, 2047 * kMiB);
  mallopt(M_TOP_PAD, 256 * kMiB);
#endif
}

}  // namespace stcweave::cli
