#pragma once

#include <memory>
#include <string>

#include "core/linear_model.h"
#include "core/nonlinearity.h"
#include "nonlinearities/contact_geometry.h"

namespace nfrc {

// The classical penalty unilateral spring by alternating frequency–time: contact force
// λ = k·max(0, −g) (N) with the gap g of ContactGeometry, i.e. k·max(0, x − g0) for an
// obstacle on the positive side. A flexible massless obstacle of stiffness k is exactly
// this law, which makes it the comparison for DLFT with obstacle_stiffness = k.
class PenaltyContact : public Nonlinearity {
 public:
  PenaltyContact(ContactGeometry geometry, double stiffness);

  std::string type() const override { return "penalty_contact"; }
  std::vector<int> Dofs() const override { return geometry_.Dofs(); }
  // A gap harmonic outside the set is an input error, found before the first solve.
  void Bind(const NonlinearityContext& ctx) override {
    geometry_.GapCoefficients(ctx.harmonic_set());
  }
  void Evaluate(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                Eigen::Ref<Eigen::VectorXd> residual, Eigen::MatrixXd* jacobian,
                Eigen::VectorXd* d_omega) const override;
  std::vector<LawSignal> Signals(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                 double omega, const FourierTransform& fine) const override;
  LawSummary Summarize(const NonlinearityContext& ctx, const Eigen::VectorXd& y, double omega,
                       const FourierTransform& fine) const override;
  std::vector<LawSignal> RawSamples(const NonlinearityContext& ctx, const Eigen::VectorXd& y,
                                    double omega) const override;
  std::map<std::string, double> Diagnostics(const NonlinearityContext& ctx,
                                            const Eigen::VectorXd& y, double omega,
                                            const FourierTransform& fine) const override;

  const ContactGeometry& geometry() const { return geometry_; }
  double stiffness() const { return stiffness_; }

 private:
  ContactState State(const NonlinearityContext& ctx, const Eigen::VectorXd& y) const;

  ContactGeometry geometry_;
  double stiffness_;  // N/m
};

}  // namespace nfrc
