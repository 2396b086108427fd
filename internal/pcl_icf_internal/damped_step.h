/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Internal to registration (not installed): the step of the refinement
 * (refinement.h, doc/icf.md eq. 6-7), exposed to unit tests. Defined in
 * registration/src/refinement.cpp. */

#include <Eigen/Core>

namespace pcl {
namespace icf {
namespace internal {

/** \brief Solve the damped 6x6 normal equations H x = -g in H's eigenbasis: along each
 * eigenvector v_k with eigenvalue l_k >= ratio * the largest, x gets -v_k (v_k . g) / (l_k + lm)
 * with lm = damping * trace(H) / 6 (Levenberg-Marquardt); degenerate directions (l_k below
 * ratio * the largest: the axis of a cylinder, the in-plane motions of a plane) stay at zero.
 * Returns the number of such directions (6, and x = 0, when H has no positive finite
 * eigenvalue). */
int solveDampedDegeneracyAware(const Eigen::Matrix<double, 6, 6>& H,
                               const Eigen::Matrix<double, 6, 1>& g, double damping, double ratio,
                               Eigen::Matrix<double, 6, 1>& x);

}  // namespace internal
}  // namespace icf
}  // namespace pcl
