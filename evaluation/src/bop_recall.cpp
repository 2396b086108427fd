/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/evaluation/bop_recall.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {
namespace evaluation {

std::size_t matchedInstances(const MatchGroup& group, double threshold) {
  const std::size_t instances = group.gt_valid.size();
  std::vector<std::size_t> order(group.estimates.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return group.estimates[a].score > group.estimates[b].score;
  });
  if (group.max_estimates > 0 && order.size() > group.max_estimates)
    order.resize(group.max_estimates);
  std::vector<bool> matched(instances, false);
  std::size_t count = 0;
  for (const std::size_t e : order) {
    const auto& errors = group.estimates[e].errors;
    if (errors.size() != instances)
      throw std::invalid_argument("MatchGroup: an estimate has " + std::to_string(errors.size()) +
                                  " errors for " + std::to_string(instances) + " instances");
    int best = -1;
    double best_error = threshold;
    for (std::size_t g = 0; g < instances; ++g)
      if (group.gt_valid[g] && !matched[g] && errors[g] < best_error) {
        best = static_cast<int>(g);
        best_error = errors[g];
      }
    if (best >= 0) {
      matched[static_cast<std::size_t>(best)] = true;
      ++count;
    }
  }
  return count;
}

double recall(const std::vector<MatchGroup>& groups, double threshold) {
  std::size_t valid = 0, matched = 0;
  for (const auto& g : groups) {
    valid += static_cast<std::size_t>(std::count(g.gt_valid.begin(), g.gt_valid.end(), true));
    matched += matchedInstances(g, threshold);
  }
  return valid == 0 ? 0.0 : static_cast<double>(matched) / static_cast<double>(valid);
}

double averageRecall(const std::vector<MatchGroup>& groups, const std::vector<double>& thresholds) {
  if (thresholds.empty())
    return 0.0;
  double sum = 0.0;
  for (const double t : thresholds)
    sum += recall(groups, t);
  return sum / static_cast<double>(thresholds.size());
}

std::vector<double> bopFractions() {
  std::vector<double> f;
  for (int k = 1; k <= 10; ++k)
    f.push_back(0.05 * k);
  return f;
}

std::vector<double> bopMspdThresholds(int width) {
  std::vector<double> t;
  for (int k = 1; k <= 10; ++k)
    t.push_back(5.0 * k * width / 640.0);
  return t;
}

}  // namespace evaluation
}  // namespace icf
}  // namespace pcl
