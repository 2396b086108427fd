/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/PointIndices.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <vector>

namespace pcl {
namespace icf {
namespace segmentation {

/** \brief Parameters of splitByConvexity (PCL's supervoxels + LCCP); lengths in scene units.
 * Defaults are PCL's LCCP example values for Kinect data. */
struct ConvexitySplitParams {
  float voxel_resolution = 0.0075f;
  float seed_resolution = 0.03f;
  float colour_importance = 0.f;
  float spatial_importance = 1.f;
  float normal_importance = 4.f;
  float concavity_tolerance_deg = 10.f;
  float smoothness_threshold = 0.1f;
  /** Segments with fewer points are dropped. */
  std::size_t min_segment_points = 150;

  void validate() const;
};

/** \brief Split one cluster of touching objects where its surface turns concave (S. Stein et
 * al., "Object Partitioning using Local Convexity", CVPR 2014, as pcl::LCCPSegmentation over
 * pcl::SupervoxelClustering). Objects standing side by side meet in concave creases; a box's
 * or a can's own edges are convex and keep it whole. Returns the segments (indices into
 * \a cloud), largest first; the cluster itself when it does not split. */
std::vector<pcl::PointIndices> splitByConvexity(const pcl::PointCloud<pcl::PointXYZRGBA>& cloud,
                                                const pcl::PointIndices& cluster,
                                                const ConvexitySplitParams& params = {});

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl
