/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <Eigen/Core>

#include <string>

namespace pcl {
namespace icf {

/** \brief Checks that \a m is a finite rigid motion: rotation block orthonormal to 1e-4,
 * determinant +1, last row (0, 0, 0, 1). The one check of every pose a user hands in (an
 * initial guess, a camera pose, a tracked pose). \throws std::invalid_argument naming \a what
 * and the broken rule. */
void validateRigidTransform(const Eigen::Matrix4d& m, const std::string& what);

}  // namespace icf
}  // namespace pcl
