/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// ADD, ADD-S and ADD-S to the surface (average_distance.h). The nearest points come from PCL's
// k-d tree and the surface distance from the model's own face index.
#include <pcl/icf/evaluation/average_distance.h>

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {
namespace evaluation {

namespace {

void checkPoints(const char* error, const std::vector<Eigen::Vector3d>& points) {
  if (points.empty())
    throw std::invalid_argument(std::string(error) + ": needs the model's points");
}

}  // namespace

double add(const Eigen::Isometry3d& est, const Eigen::Isometry3d& gt,
           const std::vector<Eigen::Vector3d>& points) {
  checkPoints("add", points);
  double sum = 0.0;
  for (const auto& x : points)
    sum += (est * x - gt * x).norm();
  return sum / static_cast<double>(points.size());
}

double adi(const Eigen::Isometry3d& est, const Eigen::Isometry3d& gt,
           const std::vector<Eigen::Vector3d>& points) {
  checkPoints("adi", points);
  // Searched in the model frame of the estimate: gt x mapped by est^-1, the tree of the points
  // themselves (distances are kept by the rigid map).
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const auto& x : points)
    cloud->push_back(pcl::PointXYZ(static_cast<float>(x.x()), static_cast<float>(x.y()),
                                   static_cast<float>(x.z())));
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  const Eigen::Isometry3d gt_in_est = est.inverse() * gt;
  std::vector<int> index(1);
  std::vector<float> squared(1);
  double sum = 0.0;
  for (const auto& x : points) {
    const Eigen::Vector3d q = gt_in_est * x;
    const pcl::PointXYZ p(static_cast<float>(q.x()), static_cast<float>(q.y()),
                          static_cast<float>(q.z()));
    tree.nearestKSearch(p, 1, index, squared);
    // The distance again in double from the point found (the tree's is float).
    sum += (points[static_cast<std::size_t>(index[0])] - q).norm();
  }
  return sum / static_cast<double>(points.size());
}

double addSToSurface(const IcfModel& model, const Eigen::Isometry3d& est,
                     const Eigen::Isometry3d& gt, const std::vector<Eigen::Vector3d>& points) {
  checkPoints("addSToSurface", points);
  const Eigen::Isometry3d gt_in_est = est.inverse() * gt;
  double sum = 0.0;
  for (const auto& x : points)
    sum += model.index().closestFace((gt_in_est * x).cast<float>()).distance;
  return sum / static_cast<double>(points.size());
}

}  // namespace evaluation
}  // namespace icf
}  // namespace pcl
