#include "validation/excitation.h"

#include <cassert>
#include <cmath>
#include <utility>

namespace nfrc {

Excitation Excitation::Harmonic(std::vector<ForcingTerm> terms, double omega) {
  Excitation e;
  e.terms = std::move(terms);
  e.omega = omega;
  return e;
}

Excitation Excitation::Chirp(std::vector<ForcingTerm> terms, double omega_start, double omega_end,
                             double duration) {
  assert(duration > 0.0);
  Excitation e;
  e.terms = std::move(terms);
  e.omega = omega_start;
  e.chirp = true;
  e.omega_end = omega_end;
  e.duration = duration;
  return e;
}

double Excitation::Phase(double t) const {
  if (!chirp) return omega * t;
  return (omega + (omega_end - omega) * t / (2.0 * duration)) * t;
}

double Excitation::InstantaneousOmega(double t) const {
  if (!chirp) return omega;
  return omega + (omega_end - omega) * t / duration;
}

void Excitation::AddForce(double t, Eigen::Ref<Eigen::VectorXd> force) const {
  const double phase = Phase(t);
  for (const ForcingTerm& term : terms) {
    assert(term.dof >= 0 && term.dof < force.size());
    const double k_phase = term.harmonic * phase;
    force(term.dof) += term.cos * std::cos(k_phase) + term.sin * std::sin(k_phase);
  }
}

void Excitation::AddForceRate(double t, Eigen::Ref<Eigen::VectorXd> rate) const {
  const double phase = Phase(t);
  const double phase_rate = InstantaneousOmega(t);  // dφ/dt
  for (const ForcingTerm& term : terms) {
    assert(term.dof >= 0 && term.dof < rate.size());
    const double k_phase = term.harmonic * phase;
    rate(term.dof) +=
        term.harmonic * phase_rate * (term.sin * std::cos(k_phase) - term.cos * std::sin(k_phase));
  }
}

}  // namespace nfrc
