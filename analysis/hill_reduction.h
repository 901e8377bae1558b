#pragma once

#include <memory>

#include "analysis/harmonic_system.h"
#include "analysis/hill.h"

namespace nfrc {

// Hill's pencil on a Craig–Bampton reduction of the system's linear model (case field
// stability.hill_modes): the DOFs the system retains stay physical (the laws act on them and
// are linearised there exactly, HillAssembler), the others are replaced by their static
// constraint modes plus the `modes` lowest fixed-interface modes. The pencil then has
// (retained + modes)·N_c unknowns instead of all DOFs'. What it drops are the exponents of the
// higher fixed-interface modes, which the contact couples to the retained DOFs only through
// their dynamic flexibility above the kept band; its error on a branch is measured against
// the full pencil (nfrc_bench 15, the README's "Hill on a reduced model").
// Throws InputError naming stability.hill_modes where the reduction cannot be built (more
// modes than interior DOFs, an interior that is not clamped).
std::shared_ptr<const HillModel> HillReduction(const HarmonicSystem& system, int modes);

}  // namespace nfrc
