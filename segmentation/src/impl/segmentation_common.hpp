/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Private to pcl_icf_segmentation's sources (not installed): what the stages' template
 * bodies share. The point-type-independent pieces are defined in src/segmentation_common.cpp. */

#include <pcl/common/point_tests.h>
#include <pcl/point_cloud.h>
#include <pcl/types.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <chrono>
#include <cstddef>
#include <memory>
#include <string>

namespace pcl::icf::segmentation::detail {

/** A shared pointer that does not own \a cloud: PCL's algorithms take ConstPtr, our stages take
 * a const reference valid for the duration of the call, so no copy is made. */
template <typename PointT>
typename pcl::PointCloud<PointT>::ConstPtr nonOwning(const pcl::PointCloud<PointT>& cloud) {
  return typename pcl::PointCloud<PointT>::ConstPtr(&cloud, [](const pcl::PointCloud<PointT>*) {});
}

/** Throws std::invalid_argument "[pcl::icf::<function>] index <index> is out of range for a
 * cloud of <size> points". */
[[noreturn]] void throwIndexOutOfRange(const char* function, pcl::index_t index, std::size_t size);

/** Throws std::invalid_argument, naming \a function, when an index is outside \a cloud. */
template <typename PointT>
void requireIndicesInRange(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
                           const char* function) {
  const auto n = static_cast<pcl::index_t>(cloud.size());
  for (const pcl::index_t i : indices) {
    if (i < 0 || i >= n)
      throwIndexOutOfRange(function, i, cloud.size());
  }
}

/** The entries of \a indices whose points are finite. Checked point by point even when
 * cloud.is_dense claims there is nothing to check: the flag is often wrong on loaded clouds. */
template <typename PointT>
pcl::Indices finiteSubset(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices) {
  pcl::Indices out;
  out.reserve(indices.size());
  for (const pcl::index_t i : indices) {
    if (pcl::isXYZFinite(cloud[i]))
      out.push_back(i);
  }
  return out;
}

/** Mean and covariance eigen-decomposition of cloud[indices], in double precision and two
 * passes (PCL's single-pass float covariance loses digits on 10^5 points far from the origin). */
struct PointSpread {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d eigenvalues = Eigen::Vector3d::Zero();       ///< increasing
  Eigen::Matrix3d eigenvectors = Eigen::Matrix3d::Identity();  ///< columns, same order
};

template <typename PointT>
PointSpread pointSpread(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices) {
  PointSpread spread;
  if (indices.empty())
    return spread;
  for (const pcl::index_t i : indices)
    spread.mean += cloud[i].getVector3fMap().template cast<double>();
  spread.mean /= static_cast<double>(indices.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const pcl::index_t i : indices) {
    const Eigen::Vector3d d = cloud[i].getVector3fMap().template cast<double>() - spread.mean;
    cov.noalias() += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
  spread.eigenvalues = solver.eigenvalues();
  spread.eigenvectors = solver.eigenvectors();
  return spread;
}

/** True when the points span at least a plane: the middle eigenvalue of their covariance is not
 * negligible against the largest. Guards RANSAC and qhull against coincident or collinear input,
 * on which PCL logs errors and gives up. */
bool spansPlane(const PointSpread& spread);

template <typename PointT>
bool spansPlane(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices) {
  return spansPlane(pointSpread(cloud, indices));
}

/** Least-squares plane (total least squares: normal = smallest principal axis) of
 * cloud[indices], with a unit normal of unspecified sign; false when they do not span a plane. */
template <typename PointT>
bool fitPlane(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
              Eigen::Vector4f& coefficients) {
  if (indices.size() < 3)
    return false;
  const PointSpread spread = pointSpread(cloud, indices);
  if (!spansPlane(spread))
    return false;
  const Eigen::Vector3d normal = spread.eigenvectors.col(0).normalized();
  coefficients.head<3>() = normal.cast<float>();
  coefficients[3] = static_cast<float>(-normal.dot(spread.mean));
  return coefficients.allFinite();
}

/** \a coefficients with the sign that puts \a origin on the positive side (kept when the origin
 * is on the plane). */
Eigen::Vector4f orientTowards(const Eigen::Vector4f& coefficients, const Eigen::Vector3f& origin);

/** Milliseconds elapsed since construction or the last lap(). */
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}

  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - start_).count();
    start_ = now;
    return ms;
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace pcl::icf::segmentation::detail
