#include "continuation/scaling.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace nfrc {
namespace {

// Absolute floor of a scale: its square (and that of 1/scale for O(1) ratios) stays a
// normal double, so scaled norms neither underflow nor overflow.
const double kTinyScale = std::sqrt(std::numeric_limits<double>::min());

}  // namespace

Scaling::Scaling(const std::vector<int>& groups, double lambda_scale, double relative_floor)
    : relative_floor_(relative_floor) {
  if (!(lambda_scale > 0.0) || !std::isfinite(lambda_scale)) {
    throw std::invalid_argument("Scaling: lambda scale must be positive and finite");
  }
  std::map<int, int> dense_index;
  group_of_.reserve(groups.size());
  for (int label : groups) {
    const auto entry = dense_index.emplace(label, static_cast<int>(dense_index.size())).first;
    group_of_.push_back(entry->second);
  }
  group_size_.assign(dense_index.size(), 0.0);
  scales_ = Eigen::VectorXd::Constant(num_unknowns() + 1, kTinyScale);
  scales_(num_unknowns()) = lambda_scale;
  Refresh();
}

void Scaling::Include(const Eigen::VectorXd& y) {
  for (int i = 0; i < num_unknowns(); ++i) {
    double& size = group_size_[group_of_[i]];
    if (std::isfinite(y(i))) size = std::max(size, std::abs(y(i)));
  }
  Refresh();
}

void Scaling::SeedZeroGroups(const Eigen::VectorXd& y_magnitude) {
  std::vector<double> seed(group_size_.size(), 0.0);
  for (int i = 0; i < num_unknowns(); ++i) {
    if (std::isfinite(y_magnitude(i))) {
      seed[group_of_[i]] = std::max(seed[group_of_[i]], std::abs(y_magnitude(i)));
    }
  }
  for (size_t g = 0; g < group_size_.size(); ++g) {
    if (group_size_[g] == 0.0) group_size_[g] = seed[g];
  }
  Refresh();
}

void Scaling::SeedZeroGroupsFromColumns(const Eigen::MatrixXd& jacobian_y) {
  std::vector<double> column(group_size_.size(), 0.0);
  double heaviest = 0.0;
  for (int i = 0; i < num_unknowns(); ++i) {
    const double norm = jacobian_y.col(i).norm();
    if (!std::isfinite(norm)) continue;
    const int g = group_of_[i];
    column[g] = std::max(column[g], norm);
    if (group_size_[g] > 0.0) heaviest = std::max(heaviest, norm * group_size_[g]);
  }
  for (size_t g = 0; g < group_size_.size(); ++g) {
    if (group_size_[g] == 0.0 && column[g] > 0.0) group_size_[g] = heaviest / column[g];
  }
  Refresh();
}

bool Scaling::HasZeroGroup() const {
  return std::find(group_size_.begin(), group_size_.end(), 0.0) != group_size_.end();
}

void Scaling::Refresh() {
  double largest = 0.0;
  for (double size : group_size_) largest = std::max(largest, size);
  const double floor = std::max(relative_floor_ * largest, kTinyScale);
  for (int i = 0; i < num_unknowns(); ++i) {
    scales_(i) = std::max(group_size_[group_of_[i]], floor);
  }
}

double LambdaScale(const ContinuationOptions& options) {
  if (options.lambda_scale > 0.0) return options.lambda_scale;
  const double scale = std::max(std::abs(options.lambda_start), std::abs(options.lambda_end));
  return scale > 0.0 ? scale : 1.0;
}

}  // namespace nfrc
