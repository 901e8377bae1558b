#pragma once

namespace nfrc {

// Keeps memory freed by the program mapped instead of returning it to the system at every
// free. A trace frees and allocates the same dense matrices (≈ 100 KB at N_φ = 60) at every
// Newton iteration; glibc trims the heap top above 128 KB by default, so each new matrix
// touched fresh pages (page faults were ~10 % of a friction trace's profile); blocks above
// 32 MiB, which glibc would always map afresh, come from the heap too. Called once by the
// programs (nfrc, nfrc_bench), not by the library: it is a process-wide setting. A no-op
// where the C library is not glibc.
void KeepFreedMemoryMapped();

}  // namespace nfrc
