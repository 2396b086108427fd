/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// The point-type-independent helpers of the stages (impl/segmentation_common.hpp).
#include "impl/segmentation_common.hpp"

#include <sstream>
#include <stdexcept>

namespace pcl {
namespace icf {
namespace segmentation {
namespace detail {

void throwIndexOutOfRange(const char* function, pcl::index_t index, std::size_t size) {
  std::ostringstream msg;
  msg << "[pcl::icf::" << function << "] index " << index << " is out of range for a cloud of "
      << size << " points";
  throw std::invalid_argument(msg.str());
}

bool spansPlane(const PointSpread& spread) {
  const Eigen::Vector3d& ev = spread.eigenvalues;
  return ev[2] > 0.0 && ev[1] > 1e-12 * ev[2];
}

Eigen::Vector4f orientTowards(const Eigen::Vector4f& coefficients, const Eigen::Vector3f& origin) {
  return coefficients.head<3>().dot(origin) + coefficients[3] < 0.0f
             ? Eigen::Vector4f(-coefficients)
             : coefficients;
}

}  // namespace detail
}  // namespace segmentation
}  // namespace icf
}  // namespace pcl
