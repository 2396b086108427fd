/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Pre-instantiation for the point types PCL's ICP is commonly used with, so users do not
// compile the class.
#include <pcl/icf/impl/iterative_closest_face.hpp>

#include <omp.h>

#include <sstream>

namespace pcl {
namespace icf {

void validateRigidTransform(const Eigen::Matrix4d& m, const std::string& what) {
  auto fail = [&](const std::string& why) {
    std::ostringstream msg;
    msg << what << " is not a rigid motion (" << why << "):\n" << m;
    throw std::invalid_argument(msg.str());
  };
  if (!m.allFinite())
    fail("a NaN or infinite entry");
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6)
    fail("last row not (0, 0, 0, 1)");
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if (!(R.transpose() * R).isIdentity(1e-4))
    fail("rotation block not orthonormal to 1e-4");
  if (R.determinant() < 0.0)
    fail("a reflection: determinant -1");
}

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
