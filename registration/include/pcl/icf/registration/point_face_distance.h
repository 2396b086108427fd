/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl {
namespace icf {

/** \brief Where on a face the closest point lies (doc/icf.md, eq. 3).
 *
 * The refinement needs it: inside a face the residual direction is the face normal; on an
 * edge or at a vertex it is (p - c) / |p - c|. */
enum class FaceFeature : int { Interior = 0, Edge = 1, Vertex = 2 };

/** \brief Closest point on one face to a query point.
 *
 * \c feature_index is the edge index k (edge from vertex k to vertex k+1, modulo the vertex
 * count) for FaceFeature::Edge, the vertex index k for FaceFeature::Vertex, and -1 inside. */
template <typename Scalar>
struct ClosestPointOnFace {
  Eigen::Matrix<Scalar, 3, 1> point = Eigen::Matrix<Scalar, 3, 1>::Zero();
  Scalar squared_distance = std::numeric_limits<Scalar>::infinity();
  FaceFeature feature = FaceFeature::Interior;
  int feature_index = -1;

  /** \brief The answer for query \a p when its closest point is \a c, on \a feature number
   * \a index of the face. */
  static ClosestPointOnFace at(const Eigen::Matrix<Scalar, 3, 1>& p,
                               const Eigen::Matrix<Scalar, 3, 1>& c, FaceFeature feature,
                               int index) {
    ClosestPointOnFace r;
    r.point = c;
    r.squared_distance = (p - c).squaredNorm();
    r.feature = feature;
    r.feature_index = index;
    return r;
  }

  /** \brief Take \a candidate when it is strictly closer (the first of equals is kept). */
  void keepCloser(const ClosestPointOnFace& candidate) {
    if (candidate.squared_distance < squared_distance)
      *this = candidate;
  }
};

/** \brief Closest point on the segment [a, b] to p, as a parameter t in [0, 1]. */
template <typename Scalar>
inline Scalar closestParameterOnSegment(const Eigen::Matrix<Scalar, 3, 1>& p,
                                        const Eigen::Matrix<Scalar, 3, 1>& a,
                                        const Eigen::Matrix<Scalar, 3, 1>& b) {
  const Eigen::Matrix<Scalar, 3, 1> ab = b - a;
  const Scalar len2 = ab.squaredNorm();
  if (!(len2 > Scalar(0)))
    return Scalar(0);
  return std::clamp((p - a).dot(ab) / len2, Scalar(0), Scalar(1));
}

/** \brief Closest point on edge \a edge = [a, b] of a face, classified as that edge or as one
 * of its end vertices (\a ia, \a ib: the indices of a and b within the face). */
template <typename Scalar>
ClosestPointOnFace<Scalar> closestPointOnFaceEdge(const Eigen::Matrix<Scalar, 3, 1>& p,
                                                  const Eigen::Matrix<Scalar, 3, 1>& a,
                                                  const Eigen::Matrix<Scalar, 3, 1>& b, int edge,
                                                  int ia, int ib);

/** \brief Exact closest point on the triangle (a, b, c) to p (Voronoi-region walk, Ericson,
 * "Real-Time Collision Detection", 5.1.5; doc/icf.md eq. 3).
 *
 * Works for any orientation; degenerate triangles (collinear or coincident vertices) fall back
 * to the closest point on their edges, so the answer is always a point of the (degenerate)
 * triangle. Edges are numbered 0 = ab, 1 = bc, 2 = ca; vertices 0 = a, 1 = b, 2 = c. */
template <typename Scalar>
ClosestPointOnFace<Scalar> closestPointOnTriangle(const Eigen::Matrix<Scalar, 3, 1>& p,
                                                  const Eigen::Matrix<Scalar, 3, 1>& a,
                                                  const Eigen::Matrix<Scalar, 3, 1>& b,
                                                  const Eigen::Matrix<Scalar, 3, 1>& c);

/** \brief Exact closest point on a planar convex polygon given by \a n vertices in order
 * (n >= 3), with its unit normal \a normal (right-handed with the vertex order).
 *
 * The projection of p decides: inside every edge's half-plane it is the interior point;
 * otherwise the closest point over all edges (segment clamping tells edge from vertex). The
 * caller guarantees planarity and convexity (FaceMesh does: other polygons are triangulated). */
template <typename Scalar>
ClosestPointOnFace<Scalar> closestPointOnConvexPolygon(const Eigen::Matrix<Scalar, 3, 1>& p,
                                                       const Eigen::Matrix<Scalar, 3, 1>* vertices,
                                                       int n,
                                                       const Eigen::Matrix<Scalar, 3, 1>& normal);

/** \brief The thesis's point-to-rectangle distance (section 4.2.2, Algorithm 1): project p on
 * the rectangle's plane, count the edges (AB, BC, CD, DA) whose segment does not contain the
 * projection of P' ("entered"); 0 means inside (plane distance), 2 an edge region (2, 4, 6, 8:
 * plane distance combined with the distance to the closest edge line), 4 a corner region (1, 3,
 * 5, 7: combined with the closest vertex). Kept as written, as a reference the general
 * closestPointOnConvexPolygon is tested against. \a corners in order A, B, C, D. */
template <typename Scalar>
ClosestPointOnFace<Scalar> closestPointOnRectangleThesis(
    const Eigen::Matrix<Scalar, 3, 1>& p, const Eigen::Matrix<Scalar, 3, 1>* corners);

}  // namespace icf
}  // namespace pcl

#include <pcl/icf/registration/impl/point_face_distance.hpp>
