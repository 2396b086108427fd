/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Internal to the libraries' sources (not installed): a model's bounding box at a pose,
 * grown by a margin on every side, as the crop of the scene points a pose is refined and judged
 * on (the localizer's hypotheses, the tracker's predicted poses). Tighter than a sphere beside
 * a neighbour: a tall cup's sphere reaches a box beside it. */

#include <pcl/icf/registration/icf_model.h>

#include <Eigen/Geometry>

namespace pcl {
namespace icf {
namespace internal {

class GrownModelBox {
 public:
  /** \a model's box at \a model_to_camera, grown by \a margin (scene units). */
  GrownModelBox(const IcfModel& model, const Eigen::Isometry3f& model_to_camera, float margin)
      : to_model_(model_to_camera.inverse(Eigen::Isometry)),
        lo_(model.mesh().boundsMin() - Eigen::Vector3f::Constant(margin)),
        hi_(model.mesh().boundsMax() + Eigen::Vector3f::Constant(margin)) {}

  /** True when the camera-frame point \a p lies inside the grown box. */
  bool contains(const Eigen::Vector3f& p) const {
    const Eigen::Vector3f x = to_model_ * p;
    return (x.array() >= lo_.array()).all() && (x.array() <= hi_.array()).all();
  }

 private:
  Eigen::Isometry3f to_model_;
  Eigen::Vector3f lo_, hi_;
};

}  // namespace internal
}  // namespace icf
}  // namespace pcl
