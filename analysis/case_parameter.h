#pragma once

#include <optional>
#include <string>

#include "analysis/case.h"

namespace nfrc {

// A numeric field of a typed Case named by its case-file path, so that studies can vary it:
// "model.forcing[0].cos", "nonlinearities[1].normal_load", "nonlinearities[0].gap". The
// fields of a law are the numeric ones of its case-file entry; of a forcing term, cos and sin.
// Copyable; it holds the path only, and every Get/Set checks the case it is given.
class CaseParameter {
 public:
  // Throws InputError naming "parameter" and the path if the path does not name a numeric
  // field of `the_case` (an index out of range, a field the law does not have).
  CaseParameter(std::string path, const Case& the_case);

  // Whether the constructor accepts `path` for `the_case`.
  static bool Accepts(const std::string& path, const Case& the_case);

  const std::string& path() const { return path_; }

  double Get(const Case& the_case) const;
  // Sets the field; the case is not validated here (Case::Validate names the field).
  void Set(Case* the_case, double value) const;
  // A copy of `the_case` with the field at `value`, validated.
  Case With(const Case& the_case, double value) const;

  // The residual's response to a unit change of the field is linear in it (forcing
  // amplitudes): ∂R/∂p then needs no step size.
  bool IsLinear() const { return kind_ == Kind::kForcingCos || kind_ == Kind::kForcingSin; }
  // The law's index for a law field ("nonlinearities[i]..."), −1 for a forcing term.
  int LawIndex() const { return kind_ == Kind::kLaw ? index_ : -1; }
  // The law's field name ("normal_load"); empty for a forcing term.
  const std::string& field() const { return field_; }

 private:
  enum class Kind { kForcingCos, kForcingSin, kLaw };
  CaseParameter() = default;
  // Reads path_ into the kind, index and field; why the path is refused, if it is.
  std::optional<std::string> Parse(const Case& the_case);
  const double* Field(const Case& the_case) const;  // null if the case has no such field

  std::string path_;
  Kind kind_ = Kind::kLaw;
  int index_ = 0;      // forcing term or law
  std::string field_;  // the law's field name
};

// How far a study in a parameter may go from the case's value (fold, peak and Neimark–Sacker
// curves): its steps are fractions of the span, so that beyond 10⁶ times the case's own value
// the smallest step leaps past the case's neighbourhood, and the curve cannot start.
inline constexpr double kMaxParameterSpan = 1e6;

// Throws InputError("to: ...") unless `to` is finite, differs from `from` (the case's value)
// and lies within kMaxParameterSpan times |from| of it (any `to` where from is 0).
void CheckStudyTarget(double from, double to);

}  // namespace nfrc
