#include "tools/allocator.h"

#include <cstdlib>  // defines __GLIBC__ on glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace nfrc {

void KeepFreedMemoryMapped() {
#if defined(__GLIBC__)
  // Setting either threshold turns off glibc's own adjustment of both, so both are set: a
  // trim threshold alone sends every block above 128 KB to mmap, page-faulting it afresh
  // (point E's 321² matrices: 7.7 → 16.9 s). Blocks up to 32 MiB (glibc's largest mmap
  // threshold) come from the heap, which keeps up to 256 MiB free at its top.
  constexpr int kTrimThresholdBytes = 256 << 20;
  constexpr int kMmapThresholdBytes = 32 << 20;
  mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes);
  mallopt(M_TRIM_THRESHOLD, kTrimThresholdBytes);
#endif
}

}  // namespace nfrc
