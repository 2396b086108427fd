/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/point_face_distance.h>

namespace pcl {
namespace icf {

template <typename Scalar>
ClosestPointOnFace<Scalar> closestPointOnFaceEdge(const Eigen::Matrix<Scalar, 3, 1>& p,
                                                  const Eigen::Matrix<Scalar, 3, 1>& a,
                                                  const Eigen::Matrix<Scalar, 3, 1>& b, int edge,
                                                  int ia, int ib) {
  using Closest = ClosestPointOnFace<Scalar>;
  const Scalar t = closestParameterOnSegment(p, a, b);
  if (t <= Scalar(0))
    return Closest::at(p, a, FaceFeature::Vertex, ia);
  if (t >= Scalar(1))
    return Closest::at(p, b, FaceFeature::Vertex, ib);
  return Closest::at(p, a + t * (b - a), FaceFeature::Edge, edge);
}

template <typename Scalar>
ClosestPointOnFace<Scalar> closestPointOnTriangle(const Eigen::Matrix<Scalar, 3, 1>& p,
                                                  const Eigen::Matrix<Scalar, 3, 1>& a,
                                                  const Eigen::Matrix<Scalar, 3, 1>& b,
                                                  const Eigen::Matrix<Scalar, 3, 1>& c) {
  using Vec = Eigen::Matrix<Scalar, 3, 1>;
  using Closest = ClosestPointOnFace<Scalar>;
  const Vec ab = b - a, ac = c - a, ap = p - a;
  const Scalar d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= Scalar(0) && d2 <= Scalar(0))
    return Closest::at(p, a, FaceFeature::Vertex, 0);

  const Vec bp = p - b;
  const Scalar d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= Scalar(0) && d4 <= d3)
    return Closest::at(p, b, FaceFeature::Vertex, 1);

  const Vec cp = p - c;
  const Scalar d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= Scalar(0) && d5 <= d6)
    return Closest::at(p, c, FaceFeature::Vertex, 2);

  const Scalar vc = d1 * d4 - d3 * d2;
  if (vc <= Scalar(0) && d1 >= Scalar(0) && d3 <= Scalar(0) && d1 - d3 > Scalar(0))
    return Closest::at(p, a + (d1 / (d1 - d3)) * ab, FaceFeature::Edge, 0);

  const Scalar vb = d5 * d2 - d1 * d6;
  if (vb <= Scalar(0) && d2 >= Scalar(0) && d6 <= Scalar(0) && d2 - d6 > Scalar(0))
    return Closest::at(p, a + (d2 / (d2 - d6)) * ac, FaceFeature::Edge, 2);

  const Scalar va = d3 * d6 - d5 * d4;
  const Scalar e43 = d4 - d3, e56 = d5 - d6;
  if (va <= Scalar(0) && e43 >= Scalar(0) && e56 >= Scalar(0) && e43 + e56 > Scalar(0))
    return Closest::at(p, b + (e43 / (e43 + e56)) * (c - b), FaceFeature::Edge, 1);

  const Scalar sum = va + vb + vc;
  if (!(sum > Scalar(0)) || !std::isfinite(sum)) {
    // Degenerate triangle: its points are its edges.
    Closest best = closestPointOnFaceEdge(p, a, b, 0, 0, 1);
    best.keepCloser(closestPointOnFaceEdge(p, b, c, 1, 1, 2));
    best.keepCloser(closestPointOnFaceEdge(p, c, a, 2, 2, 0));
    return best;
  }
  const Scalar v = vb / sum, w = vc / sum;
  return Closest::at(p, a + v * ab + w * ac, FaceFeature::Interior, -1);
}

template <typename Scalar>
ClosestPointOnFace<Scalar> closestPointOnConvexPolygon(const Eigen::Matrix<Scalar, 3, 1>& p,
                                                       const Eigen::Matrix<Scalar, 3, 1>* vertices,
                                                       int n,
                                                       const Eigen::Matrix<Scalar, 3, 1>& normal) {
  using Vec = Eigen::Matrix<Scalar, 3, 1>;
  using Closest = ClosestPointOnFace<Scalar>;
  if (n == 3)
    return closestPointOnTriangle(p, vertices[0], vertices[1], vertices[2]);
  bool inside = true;
  for (int k = 0; k < n && inside; ++k) {
    const Vec& a = vertices[k];
    const Vec& b = vertices[(k + 1) % n];
    inside = (b - a).cross(p - a).dot(normal) >= Scalar(0);
  }
  if (inside) {
    const Vec c = p - normal.dot(p - vertices[0]) * normal;
    return Closest::at(p, c, FaceFeature::Interior, -1);
  }
  ClosestPointOnFace<Scalar> best;
  for (int k = 0; k < n; ++k)
    best.keepCloser(
        closestPointOnFaceEdge(p, vertices[k], vertices[(k + 1) % n], k, k, (k + 1) % n));
  return best;
}

template <typename Scalar>
ClosestPointOnFace<Scalar> closestPointOnRectangleThesis(
    const Eigen::Matrix<Scalar, 3, 1>& p, const Eigen::Matrix<Scalar, 3, 1>* corners) {
  using Vec = Eigen::Matrix<Scalar, 3, 1>;
  using Closest = ClosestPointOnFace<Scalar>;
  const Vec normal = (corners[1] - corners[0]).cross(corners[3] - corners[0]).normalized();
  const Vec projected = p - normal.dot(p - corners[0]) * normal;  // P'
  // "The projection of P' belongs to segment AB if AP'.AB >= 0 and BP'.BA >= 0."
  auto projectionInside = [&](const Vec& a, const Vec& b) {
    return (projected - a).dot(b - a) >= Scalar(0) && (projected - b).dot(a - b) >= Scalar(0);
  };
  int entered = 0;
  for (int k = 0; k < 4; ++k)
    entered += projectionInside(corners[k], corners[(k + 1) % 4]) ? 0 : 1;

  if (entered == 0)
    return Closest::at(p, projected, FaceFeature::Interior, -1);
  ClosestPointOnFace<Scalar> best;
  if (entered == 2) {
    // Regions 2, 4, 6, 8: d = sqrt(d(P, P')^2 + d(P', closest edge)^2). The closest edge is
    // the nearer of the two whose segment contains the projection of P'.
    for (int k = 0; k < 4; ++k) {
      const Vec& a = corners[k];
      const Vec& b = corners[(k + 1) % 4];
      if (!projectionInside(a, b))
        continue;
      const Scalar t = closestParameterOnSegment(projected, a, b);
      best.keepCloser(Closest::at(p, a + t * (b - a), FaceFeature::Edge, k));
    }
    return best;
  }
  // Regions 1, 3, 5, 7: d = sqrt(d(P, P')^2 + d(P', closest vertex)^2).
  for (int k = 0; k < 4; ++k)
    best.keepCloser(Closest::at(p, corners[k], FaceFeature::Vertex, k));
  return best;
}

}  // namespace icf
}  // namespace pcl
