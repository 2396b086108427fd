/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Internal to the libraries' sources (not installed): at most so many poses of one
 * place, so that a quota of poses taken best first also reaches a second object or a second
 * copy (the point pair votes kept, the localizer's hypotheses judged). */

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace pcl {
namespace icf {
namespace internal {

class PlaceQuota {
 public:
  /** Places are points within \a radius of the first point offered there; each admits
   * \a per_place. */
  PlaceQuota(float radius, std::size_t per_place) : radius_(radius), per_place_(per_place) {}

  /** Counts \a point at its place (a new place when none lies within the radius) and returns
   * whether the place had room for it. */
  bool admit(const Eigen::Vector3f& point) {
    std::size_t place = 0;
    while (place < places_.size() && (places_[place] - point).norm() > radius_)
      ++place;
    if (place == places_.size()) {
      places_.push_back(point);
      counts_.push_back(0);
    }
    return counts_[place]++ < per_place_;
  }

 private:
  float radius_;
  std::size_t per_place_;
  std::vector<Eigen::Vector3f> places_;
  std::vector<std::size_t> counts_;
};

}  // namespace internal
}  // namespace icf
}  // namespace pcl
