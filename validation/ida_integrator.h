#pragma once

#include "validation/transient.h"
#include "validation/transient_model.h"

namespace nfrc {

// SUNDIALS IDA (BDF, variable order and step) integration of a TransientModel with its
// time-domain laws: DAE residual F(t, y, ẏ) of time_law.h plus four quadrature states (energy
// integral, input work, damping dissipation, law work), root functions of the laws' current
// modes, a stop at every root, a mode switch (iterated until every law is admissible), and a
// re-initialisation with consistent ẏ and algebraic values. Dense linear solver up to
// TransientOptions::kDenseLimit unknowns, KLU beyond. An undamped massless DOF on which a law
// with a differential own unknown acts (exact friction on a massless slider, index 2 while
// sliding) has its momentum row differentiated in time and projected back onto the original
// row at every restart. The model must have no rigid contacts.
class IdaIntegrator : public TransientIntegrator {
 public:
  // Keeps a reference to `model`, whose laws' modes it changes.
  IdaIntegrator(TransientModel& model, TransientOptions options);
  ~IdaIntegrator() override;

  TransientResult RunToSteadyState(double omega, const InitialState& start) override;
  ChirpResult RunChirp(const Excitation& chirp, int samples_per_cycle) override;

 private:
  TransientModel& model_;
  TransientOptions options_;
};

}  // namespace nfrc
