/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Pre-instantiation for the point types PCL's ICP is commonly used with, so users do not
// compile the class.
#include <pcl/icf/registration/impl/iterative_closest_face.hpp>

#include <omp.h>

#include <sstream>

namespace pcl {
namespace icf {

std::size_t countPointsNearSurface(const ClosestFaceQuery& index,
                                   const std::vector<Eigen::Vector3f>& points,
                                   const Eigen::Isometry3f& scene_to_model, float radius,
                                   int threads) {
  const int n = static_cast<int>(points.size());
  long count = 0;
#pragma omp parallel for reduction(+ : count) num_threads(threads > 0 ? threads : omp_get_num_procs())
  for (int i = 0; i < n; ++i)
    count +=
        index.closestFace(scene_to_model * points[static_cast<std::size_t>(i)], radius).distance <=
        radius;
  return static_cast<std::size_t>(count);
}

}  // namespace icf
}  // namespace pcl

#define PCL_ICF_INSTANTIATE(T)                   \
  template class pcl::icf::MeshSurfaceSearch<T>; \
  template class pcl::IterativeClosestFace<T, float>;

PCL_ICF_INSTANTIATE(pcl::PointXYZ)
PCL_ICF_INSTANTIATE(pcl::PointXYZI)
PCL_ICF_INSTANTIATE(pcl::PointXYZRGB)
PCL_ICF_INSTANTIATE(pcl::PointXYZRGBA)
PCL_ICF_INSTANTIATE(pcl::PointNormal)
PCL_ICF_INSTANTIATE(pcl::PointXYZRGBNormal)
PCL_ICF_INSTANTIATE(pcl::PointXYZINormal)
template class pcl::IterativeClosestFace<pcl::PointXYZ, double>;
