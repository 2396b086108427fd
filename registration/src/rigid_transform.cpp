/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/rigid_transform.h>

#include <Eigen/LU>

#include <sstream>
#include <stdexcept>

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

}  // namespace icf
}  // namespace pcl
