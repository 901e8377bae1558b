#pragma once

#include <atomic>
#include <iosfwd>
#include <string>

#include "continuation/branch.h"
#include "tools/case_file.h"

namespace nfrc {

// `nfrc run` for continuation.method "lemke_stepping": LCP-HBM by natural-parameter stepping
// (the paper's way to an NFRC with Lemke). At each ω of an even grid from omega_start to
// omega_end (plus the case's signals_at), Lemke solves g = W λ + p from its cold start. It
// returns the trivial solution λ = 0 whenever the linear response does not penetrate
// (p ≥ 0), even where a contact branch coexists past a turning point. With track_contact,
// where the cold solve is trivial but the previous point had contact, Lemke is warm-started
// from the previous contact basis; a non-trivial solution found that way is the coexisting
// contact solution, recorded with the point (the point itself stays the cold solution).
//
// Writes DIR/branch.json and branch.csv like `nfrc run`; every point carries "lcp": status,
// pivots, trivial, complementarity and feasibility (scaled Lemke residuals),
// complementarity_gap (m), coexisting_contact and, if so, "contact_branch" with the warm
// solution's measures. A point where Lemke fails is recorded in the summary's history and
// skipped. Returns the points; throws InputError if a law is not lcp_contact.
Branch RunLcpStepping(Case& the_case, const std::string& out_dir, std::ostream* progress,
                      const std::atomic<bool>* stop = nullptr);

}  // namespace nfrc
