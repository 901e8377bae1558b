#include "continuation/closure.h"

namespace nfrc {
namespace {

// The branch counts as away once a point is this many chords from the first point.
constexpr double kAwayChords = 1.5;
// Largest distance of the first point from the step's chord, in chords: the arc of a step
// whose tangent turns by at most max_tangent_angle deviates from its chord far less.
constexpr double kClosureDistance = 0.25;
// Smallest cosine between the tangents at the first and the closing point (60°), so a
// branch passing the first point in the opposite direction is not taken as closed.
constexpr double kClosureMinCosine = 0.5;

}  // namespace

ClosureDetector::ClosureDetector(const Eigen::VectorXd& u_first,
                                 const Eigen::VectorXd& tangent_first)
    : u_first_(u_first), tangent_first_(tangent_first) {}

bool ClosureDetector::Closes(const Scaling& scaling, const Eigen::VectorXd& u_previous,
                             const Eigen::VectorXd& u_new, const Eigen::VectorXd& tangent_new) {
  const Eigen::VectorXd chord = scaling.ToScaled(u_new - u_previous);
  const double chord_length = chord.norm();
  if (!(chord_length > 0.0)) return false;
  if (!away_) {
    away_ = scaling.Norm(u_new - u_first_) > kAwayChords * chord_length;
    return false;
  }
  const Eigen::VectorXd to_first = scaling.ToScaled(u_first_ - u_previous);
  const double along = to_first.dot(chord) / (chord_length * chord_length);
  if (along < 0.0 || along > 1.0) return false;
  if ((to_first - along * chord).norm() > kClosureDistance * chord_length) return false;
  return scaling.UnitScaled(tangent_new).dot(scaling.UnitScaled(tangent_first_)) >=
         kClosureMinCosine;
}

}  // namespace nfrc
