#pragma once

#include "validation/transient.h"
#include "validation/transient_driver.h"
#include "validation/transient_model.h"

namespace nfrc {

// The transient driver over SUNDIALS IDA (validation/ida_stepper.h): integration of a
// TransientModel with its time-domain laws, events and consistent re-initialisations, exact
// friction on a massless DOF by index reduction. The model must have no rigid contacts.
class IdaIntegrator : public TransientDriver {
 public:
  // Keeps a reference to `model`, whose laws' modes it changes (and whose massless flags it
  // fills from M if empty). Throws InputError for bad options or a rigid contact.
  IdaIntegrator(TransientModel& model, TransientOptions options);
  ~IdaIntegrator() override;
};

}  // namespace nfrc
