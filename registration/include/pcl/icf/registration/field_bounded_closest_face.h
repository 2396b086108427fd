/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/closest_face_query.h>
#include <pcl/icf/registration/distance_field.h>

#include <algorithm>
#include <limits>

namespace pcl {
namespace icf {

/** \brief Exact closest-face queries that start small: each query's radius is first cut to the
 * closest-point field's strict upper bound on the distance (ClosestPointField::
 * distanceUpperBound, about the distance plus a cell), so the BVH visits the few faces near the
 * answer instead of every face within the caller's radius (a refinement's Tukey radius, the
 * quality measure's gate). The closest face lies within that bound, so the answers are the
 * exact index's (tested against the brute force); only ties between faces at the same distance
 * may go to another of the tied faces.
 *
 * Keeps references to the exact index and the field: both must outlive it. */
class FieldBoundedClosestFace : public ClosestFaceQuery {
 public:
  FieldBoundedClosestFace(const ClosestFaceQuery& exact, const ClosestPointField& field)
      : ClosestFaceQuery(exact.mesh()), exact_(exact), field_(field) {}

  ClosestFace closestFace(
      const Eigen::Vector3f& p,
      float max_distance = std::numeric_limits<float>::infinity()) const override {
    // min(max_distance, bound): a NaN max_distance stays NaN (nothing found, as the exact
    // index answers), a non-finite point gets an infinite bound and the exact index's answer.
    return exact_.closestFace(p, std::min(max_distance, field_.distanceUpperBound(p)));
  }

 private:
  const ClosestFaceQuery& exact_;
  const ClosestPointField& field_;
};

}  // namespace icf
}  // namespace pcl
