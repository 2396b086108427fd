/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/segmentation/convexity_split.h>
#include <pcl/segmentation/lccp_segmentation.h>
#include <pcl/segmentation/supervoxel_clustering.h>
#include <pcl_icf_internal/parameter_check.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

namespace pcl {
namespace icf {
namespace segmentation {

void ConvexitySplitParams::validate() const {
  const internal::ParameterCheck fail("segmentation::ConvexitySplitParams");
  if (!(voxel_resolution > 0.f) || !std::isfinite(voxel_resolution))
    fail("voxel_resolution", voxel_resolution, "must be positive and finite");
  if (!(seed_resolution > voxel_resolution) || !std::isfinite(seed_resolution))
    fail("seed_resolution", seed_resolution, "must be finite and > voxel_resolution");
  if (!(concavity_tolerance_deg > 0.f && concavity_tolerance_deg < 90.f))
    fail("concavity_tolerance_deg", concavity_tolerance_deg, "must lie in (0, 90)");
}

std::vector<pcl::PointIndices> splitByConvexity(const pcl::PointCloud<pcl::PointXYZRGBA>& cloud,
                                                const pcl::PointIndices& cluster,
                                                const ConvexitySplitParams& params) {
  params.validate();
  auto points = pcl::make_shared<pcl::PointCloud<pcl::PointXYZRGBA>>();
  points->reserve(cluster.indices.size());
  for (const auto i : cluster.indices)
    points->push_back(cloud[static_cast<std::size_t>(i)]);
  if (points->size() < 2 * params.min_segment_points)
    return {cluster};

  pcl::SupervoxelClustering<pcl::PointXYZRGBA> supervoxels(params.voxel_resolution,
                                                           params.seed_resolution);
  supervoxels.setUseSingleCameraTransform(false);
  supervoxels.setInputCloud(points);
  supervoxels.setColorImportance(params.colour_importance);
  supervoxels.setSpatialImportance(params.spatial_importance);
  supervoxels.setNormalImportance(params.normal_importance);
  std::map<std::uint32_t, pcl::Supervoxel<pcl::PointXYZRGBA>::Ptr> clusters;
  supervoxels.extract(clusters);
  if (clusters.size() < 2)
    return {cluster};
  std::multimap<std::uint32_t, std::uint32_t> adjacency;
  supervoxels.getSupervoxelAdjacency(adjacency);

  pcl::LCCPSegmentation<pcl::PointXYZRGBA> lccp;
  lccp.setConcavityToleranceThreshold(params.concavity_tolerance_deg);
  lccp.setSmoothnessCheck(true, params.voxel_resolution, params.seed_resolution,
                          params.smoothness_threshold);
  lccp.setSanityCheck(true);
  lccp.setKFactor(0);
  lccp.setInputSupervoxels(clusters, adjacency);
  lccp.segment();
  pcl::PointCloud<pcl::PointXYZL>::Ptr labels = supervoxels.getLabeledCloud();
  lccp.relabelCloud(*labels);
  if (labels->size() != points->size())
    return {cluster};

  std::map<std::uint32_t, pcl::PointIndices> segments;
  for (std::size_t k = 0; k < labels->size(); ++k)
    if ((*labels)[k].label != 0)
      segments[(*labels)[k].label].indices.push_back(cluster.indices[k]);
  std::vector<pcl::PointIndices> out;
  for (auto& kv : segments)
    if (kv.second.indices.size() >= params.min_segment_points)
      out.push_back(std::move(kv.second));
  std::stable_sort(out.begin(), out.end(),
                   [](const pcl::PointIndices& a, const pcl::PointIndices& b) {
                     return a.indices.size() > b.indices.size();
                   });
  if (out.empty())
    return {cluster};
  return out;
}

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl
