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
  // (point E's 321² matrices: 7.7 → 16.9 s). The heap keeps up to 256 MiB free at its top.
  // Blocks above 32 MiB (glibc's largest mmap threshold) would still be mapped at each
  // allocation: mmap off, they come from the heap too (the N_φ = 640 point's 2 561²
  // matrices: 120 000 → 66 000 page faults, −10 %). The price is that blocks freed inside
  // the heap stay mapped (the 10⁵-DOF blade's peak: 765 → 833 MB).
  constexpr int kTrimThresholdBytes = 256 << 20;
  constexpr int kMmapThresholdBytes = 32 << 20;
  mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes);
  mallopt(M_TRIM_THRESHOLD, kTrimThresholdBytes);
  mallopt(M_MMAP_MAX, 0);
#endif
}

}  // namespace nfrc
