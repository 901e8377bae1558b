#pragma once

#include <memory>
#include <string>
#include <vector>

#include "validation/stepper.h"
#include "validation/transient.h"
#include "validation/transient_model.h"

namespace nfrc {

// SUNDIALS IDA (BDF, variable order and step) as a TransientStepper: the DAE of
// validation/ida_dae.h with its four quadratures, root functions of the laws' current modes,
// a stop at every root, a mode switch (iterated until every law is admissible) and a
// re-initialisation with consistent ẏ and algebraic values. Dense linear solver up to
// TransientOptions::kDenseLimit unknowns, KLU beyond; largest step max_step_fraction of the
// shortest excitation period; absolute tolerances scaled by the linear response
// (validation/linear_response.h). Statistics are IDA's counters summed over every
// re-initialisation. The model must have no rigid contacts.
class IdaStepper : public TransientStepper {
 public:
  // Keeps a reference to `model`, whose laws' modes it changes; fills model.massless from M
  // if it is empty. Throws InputError if the model has a rigid contact.
  IdaStepper(TransientModel& model, const TransientOptions& options);
  ~IdaStepper() override;

  std::string method() const override { return "ida"; }
  bool Start(const StepperStart& start) override;
  bool BeginSegment(double t_end) override;
  StepOutcome AdvanceTo(double t) override;
  bool ResetQuadratures() override;
  double t() const override;
  Eigen::Ref<const Eigen::VectorXd> x() const override;
  Eigen::Ref<const Eigen::VectorXd> v() const override;
  Eigen::VectorXd own() const override;
  LawSignalValues Signals() const override;
  const std::vector<LawPhaseLog>& PhaseLogs() const override;
  StepperQuadratures Quadratures() const override;
  TransientStatistics Statistics() const override;
  const std::string& message() const override;

 private:
  class Run;  // one integration: the SUNDIALS objects and the DAE

  TransientModel& model_;
  TransientOptions options_;
  std::unique_ptr<Run> run_;
  std::string message_;  // of a failure before a run exists
};

}  // namespace nfrc
