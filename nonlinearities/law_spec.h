#pragma once

#include <memory>
#include <optional>
#include <string_view>
#include <variant>
#include <vector>

#include "core/linear_model.h"
#include "core/nonlinearity.h"
#include "nonlinearities/contact_geometry.h"
#include "nonlinearities/friction_equality.h"
#include "nonlinearities/polynomial_spring.h"

namespace nfrc {

// Typed, copyable specifications of the laws: what a case says about a law, as values.
// A case holds these (never built laws), so it can be copied and changed (harmonics, ε,
// a normal load) and systems built from it as often as needed. Each Validate() throws
// InputError naming the field relative to the law ("mu: must be non-negative"); readers
// prefix the law's path. Field names are the case file's.

// k₃u³ on u = x_dof − x_other.
struct CubicSpringSpec {
  static constexpr std::string_view kType = "cubic_spring";
  int dof = -1;
  int other = -1;            // −1: against ground
  double coefficient = 0.0;  // N/m³
  void Validate(const LinearModel& model) const;
  // The harmonic-balance law (defined with the law).
  std::unique_ptr<Nonlinearity> MakeHarmonic(const LinearModel& model) const;
};

// Σ c_p u^p, p ≥ 2.
struct PolynomialSpringSpec {
  static constexpr std::string_view kType = "polynomial_spring";
  int dof = -1;
  int other = -1;
  std::vector<PolynomialSpring::Term> terms;
  void Validate(const LinearModel& model) const;
  // The harmonic-balance law (defined with the law).
  std::unique_ptr<Nonlinearity> MakeHarmonic(const LinearModel& model) const;
};

// Equality-based Coulomb friction (Legrand & Pierre 2024) under a constant normal load.
struct CoulombFrictionSpec {
  static constexpr std::string_view kType = "coulomb_friction";
  int dof = -1;
  int other = -1;
  double mu = 0.0;           // friction coefficient
  double normal_load = 0.0;  // N
  FrictionEquality law = FrictionEquality::kMinMax;
  double rho = 1.0;    // ρ of the exact laws (velocity / force)
  double alpha = 0.0;  // α of tanh and arctan (1 / velocity); required by them
  double delta = 0.0;  // δ of piecewise_linear (velocity); required by it
  FrictionParameters Parameters() const;
  void Validate(const LinearModel& model) const;
  // The harmonic-balance law (defined with the law).
  std::unique_ptr<Nonlinearity> MakeHarmonic(const LinearModel& model) const;
};

// Jenkins element: a spring k_t in series with a Coulomb slider μN (elastic dry friction).
struct JenkinsSpec {
  static constexpr std::string_view kType = "jenkins";
  int dof = -1;
  int other = -1;
  double mu = 0.0;           // friction coefficient
  double normal_load = 0.0;  // N
  double stiffness = 0.0;    // k_t, N/m
  void Validate(const LinearModel& model) const;
  // The harmonic-balance law (defined with the law).
  std::unique_ptr<Nonlinearity> MakeHarmonic(const LinearModel& model) const;
};

// k·max(0, −g): a flexible obstacle of stiffness k.
struct PenaltyContactSpec {
  static constexpr std::string_view kType = "penalty_contact";
  ContactGeometry geometry;
  double stiffness = 0.0;  // N/m
  void Validate(const LinearModel& model) const;
  // The harmonic-balance law (defined with the law).
  std::unique_ptr<Nonlinearity> MakeHarmonic(const LinearModel& model) const;
};

// Unilateral contact by DLFT (Vadcard et al. 2022).
struct DlftContactSpec {
  static constexpr std::string_view kType = "dlft_contact";
  LagrangianContactSpec contact;
  void Validate(const LinearModel& model) const;
  // The harmonic-balance law (defined with the law).
  std::unique_ptr<Nonlinearity> MakeHarmonic(const LinearModel& model) const;
};

// Unilateral contact as a complementarity problem on the samples (LCP-HBM).
struct LcpContactSpec {
  static constexpr std::string_view kType = "lcp_contact";
  LagrangianContactSpec contact;
  double smoothing = 0.0;  // m, 0 = exact complementarity
  void Validate(const LinearModel& model) const;
  // The harmonic-balance law (defined with the law).
  std::unique_ptr<Nonlinearity> MakeHarmonic(const LinearModel& model) const;
};

// Coulomb friction by DLFT (Nacivet et al. 2003): displacement unknowns, the force predicted
// from the linear equations and corrected for stick/slip sample by sample with weight ε.
struct DlftFrictionSpec {
  static constexpr std::string_view kType = "dlft_friction";
  int dof = -1;
  int other = -1;
  double mu = 0.0;           // friction coefficient
  double normal_load = 0.0;  // N
  double epsilon = 0.0;      // N/m, 0 = default: the model's diagonal stiffness at the DOF(s)
  void Validate(const LinearModel& model) const;
  // ε in use (N/m) for a model: `epsilon`, or the mean of K's diagonal over the law's DOFs.
  double EpsilonFor(const LinearModel& model) const;
  // The harmonic-balance law (defined with the law); its default ε reads the model.
  std::unique_ptr<Nonlinearity> MakeHarmonic(const LinearModel& model) const;
};

// Unilateral contact by the equality-based weighted-residual formulation (Signorini as
// min(λ, ρg) = 0 projected on the harmonics).
struct EqualityContactSpec {
  static constexpr std::string_view kType = "equality_contact";
  ContactGeometry geometry;
  double obstacle_stiffness = 0.0;  // N/m, 0 = rigid
  double rho = 0.0;                 // N/m, 0 = default (obstacle stiffness, else static stiffness)
  void Validate(const LinearModel& model) const;
  // The harmonic-balance law (defined with the law).
  std::unique_ptr<Nonlinearity> MakeHarmonic(const LinearModel& model) const;
};

// Unilateral contact with Coulomb friction under the contact force (equality-based: Signorini on
// the normal gap, Coulomb with the limit μλ(t) on a tangent DOF). A preload is a static force in
// the model's forcing (harmonic 0).
struct ContactFrictionSpec {
  static constexpr std::string_view kType = "contact_friction";
  ContactGeometry geometry;         // the normal gap: dof, other, direction, gap
  double obstacle_stiffness = 0.0;  // N/m, 0 = rigid
  int tangent_dof = -1;
  int tangent_other = -1;     // −1: sliding on the obstacle
  double mu = 0.0;            // friction coefficient
  double rho = 0.0;           // N/m, 0 = default (as equality_contact)
  double friction_rho = 1.0;  // ρ of the friction equality (velocity / force)
  void Validate(const LinearModel& model) const;
  // The harmonic-balance law (defined with the law).
  std::unique_ptr<Nonlinearity> MakeHarmonic(const LinearModel& model) const;
};

// The law registry: one alternative per law. Adding a law adds its spec here; its harmonic
// law (MakeHarmonicLaw below) and its time-domain law (AddTimeLaw in validation/transient_model.cc)
// are then required by the compiler, and the reader finds it by kType.
using LawSpec = std::variant<CubicSpringSpec, PolynomialSpringSpec, CoulombFrictionSpec,
                             JenkinsSpec, PenaltyContactSpec, DlftContactSpec, LcpContactSpec,
                             EqualityContactSpec, DlftFrictionSpec, ContactFrictionSpec>;

// The case-file "type" of a spec (for messages and outputs).
std::string_view LawType(const LawSpec& spec);

// The contact geometry of a contact law's spec; null for the other laws.
const ContactGeometry* LawContactGeometry(const LawSpec& spec);

// The model DOFs a spec acts on.
std::vector<int> LawDofs(const LawSpec& spec);

// Renumbers the DOFs a spec acts on: dof → new_index[dof] (a reduced model's numbering).
void RemapLawDofs(LawSpec& spec, const std::vector<int>& new_index);

// The stiffness (N/m) through which a law tends to its nonsmooth limit as it grows, where a
// start can be softened: jenkins' k_t, dlft_friction's ε (its default resolved on `model`),
// penalty_contact's k. Empty for the other laws (dlft_contact's default ε needs the
// condensation; `nfrc refine` continues in it).
std::optional<double> LawStiffness(const LawSpec& spec, const LinearModel& model);

// Sets the stiffness LawStiffness reads; std::logic_error for a law without one.
void SetLawStiffness(LawSpec& spec, double stiffness);

// Validate() of the alternative held.
void ValidateLaw(const LawSpec& spec, const LinearModel& model);

// How far either way of the model's own scale a law's numerical parameter may lie: its
// stiffness-like ones (N/m: a Jenkins or penalty stiffness, DLFT's ε, the equality laws' ρ,
// an obstacle's stiffness) against the largest diagonal stiffness at the law's DOFs, a friction
// equality's ρ (velocity per force) against 1/√(k m) there. 10¹² either way leaves four of
// double precision's sixteen digits to the smaller term; beyond it the solvers stall, overflow
// or find no tangent with nothing to name the cause.
inline constexpr double kUsefulParameterRatio = 1e12;

// Throws InputError naming the field ("rho: 1e+300 N/m lies outside its useful range [...]")
// where a parameter of a user's law lies outside kUsefulParameterRatio of the model's scale.
// For what a case states (Case::Validate): the start's stiffness homotopy and the ε
// refinement go beyond the case's value on purpose and do not pass through it.
void CheckLawRanges(const LawSpec& spec, const LinearModel& model);

// The harmonic-balance law of a spec (validated first).
std::unique_ptr<Nonlinearity> MakeHarmonicLaw(const LawSpec& spec, const LinearModel& model);

}  // namespace nfrc
