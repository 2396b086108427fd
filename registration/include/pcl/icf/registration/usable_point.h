/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <Eigen/Core>

namespace pcl {
namespace icf {

/** \brief Scene points with a coordinate beyond this (scene units: 1000 km in metres) are
 * treated like NaN ones, by estimatePose and by the table-top segmentation: no sensor measures
 * them, float geometry on them overflows (their squared distances are infinite), and a few of
 * them would drag every centroid, bounding box and plane fit away from the scene. */
constexpr float kMaxPointCoordinate = 1e6f;

/** \brief True when every coordinate of \a p is finite and within +-kMaxPointCoordinate. */
inline bool isUsablePoint(const Eigen::Vector3f& p) {
  return p.allFinite() && p.cwiseAbs().maxCoeff() <= kMaxPointCoordinate;
}

}  // namespace icf
}  // namespace pcl
