/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/closest_face_query.h>

#include <array>

namespace pcl {
namespace icf {

ClosestPointOnFace<float> closestPointOnMeshFace(const FaceMesh& mesh, std::size_t f,
                                                 const Eigen::Vector3f& p) {
  const Face& face = mesh.faces()[f];
  if (face.count == 3)
    return closestPointOnTriangle(p, mesh.faceVertex(f, 0), mesh.faceVertex(f, 1),
                                  mesh.faceVertex(f, 2));
  constexpr std::uint32_t kStack = 16;
  std::array<Eigen::Vector3f, kStack> stack;
  std::vector<Eigen::Vector3f> heap;
  Eigen::Vector3f* corners = stack.data();
  if (face.count > kStack) {
    heap.resize(face.count);
    corners = heap.data();
  }
  for (std::uint32_t k = 0; k < face.count; ++k)
    corners[k] = mesh.faceVertex(f, k);
  return closestPointOnConvexPolygon(p, corners, static_cast<int>(face.count), face.normal);
}

Eigen::Vector3f residualDirection(const FaceMesh& mesh, const Eigen::Vector3f& p,
                                  const ClosestFace& closest) {
  const Eigen::Vector3f& n = mesh.faces()[static_cast<std::size_t>(closest.face)].normal;
  const Eigen::Vector3f offset = p - closest.point;
  const float length = offset.norm();
  if (closest.feature == FaceFeature::Interior || !(length > 1e-9f))
    return offset.dot(n) >= 0.f ? n : Eigen::Vector3f(-n);
  return offset / length;
}

ClosestFace BruteForceClosestFace::closestFace(const Eigen::Vector3f& p, float max_distance) const {
  ClosestFace best;
  if (!p.allFinite())
    return best;
  float best_sq = max_distance * max_distance;
  for (std::size_t f = 0; f < mesh_.size(); ++f) {
    const ClosestPointOnFace<float> c = closestPointOnMeshFace(mesh_, f, p);
    if (c.squared_distance < best_sq || (best.face < 0 && c.squared_distance <= best_sq)) {
      best_sq = c.squared_distance;
      best.point = c.point;
      best.face = static_cast<int>(f);
      best.feature = c.feature;
      best.feature_index = c.feature_index;
    }
  }
  if (best.found())
    best.distance = std::sqrt(best_sq);
  return best;
}

}  // namespace icf
}  // namespace pcl
