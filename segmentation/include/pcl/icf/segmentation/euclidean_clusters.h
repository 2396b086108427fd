/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/PointIndices.h>
#include <pcl/icf/segmentation/precompiled_point_types.h>
#include <pcl/point_cloud.h>
#include <pcl/types.h>

#include <cstddef>
#include <string>
#include <vector>

namespace pcl {
namespace icf {
namespace segmentation {

/** \brief How extractClusters finds the connected components. All three give the same clusters:
 * the connected components of the graph that links two points when their distance is <= the
 * tolerance (checked against each other by the tests on the milk scene and mOSD). */
enum class ClusterMethod {
  /** Our exact grid algorithm: points are binned into cubic cells of edge tolerance / sqrt(3),
   * so each cell is a clique; two cells up to two cells apart are joined (union-find) as soon as
   * one pair of their points is within tolerance. No radius search per point: at the 2 cm
   * tolerance on the 640x480 scenes (50k-100k points above the table) it takes 13-19 ms where
   * pcl::EuclideanClusterExtraction takes 135-280 ms with OrganizedNeighbor and 300-650 ms with
   * a kd-tree (tools/pcl_icf_bench/micro/segmentation_bench.cpp). Its cost grows with the number
   * of occupied cells, so at tolerances of 5 mm and less OrganizedNeighbor can be faster. Falls
   * back to PclKdTree when the points span more than 2^20 cells along an axis. */
  Grid,
  /** pcl::EuclideanClusterExtraction with pcl::search::KdTree (FLANN), the reference. */
  PclKdTree,
  /** pcl::EuclideanClusterExtraction with pcl::search::OrganizedNeighbor (organized clouds only;
   * falls back to PclKdTree on an unorganized cloud). */
  PclOrganized
};

/** \brief "Grid", "PclKdTree" or "PclOrganized". */
std::string toString(ClusterMethod method);

/** \brief Parameters of the Euclidean clustering stage. */
struct ClusterParams {
  /** Two points are in the same cluster when a chain of points links them with steps shorter
   * than tolerance, in scene units (metres). Must be finite and > 0. Default 0.02 (2 cm, as in
   * the thesis). */
  double tolerance = 0.02;
  /** Smaller clusters are dropped. Must be >= 1. Default 100. */
  std::size_t min_size = 100;
  /** Larger clusters are dropped. Must be >= min_size. Default 250000. */
  std::size_t max_size = 250000;
  /** Algorithm; all give the same clusters. Default Grid (the fastest by far, see
   * ClusterMethod). */
  ClusterMethod method = ClusterMethod::Grid;

  /** \brief Throws std::invalid_argument naming the field and its value when a field is out of
   * range. */
  void validate() const;
};

/** \brief Euclidean clusters of \a cloud[indices] (the clusters of
 * pcl::EuclideanClusterExtraction, computed as params.method says), in a deterministic order.
 *
 * \param[in] cloud  read only during the call.
 * \param[in] indices  the points to cluster (each < cloud.size()); non-finite ones are skipped.
 * \param[in] params  see ClusterParams.
 * \return the clusters with min_size..max_size points, each as indices into \a cloud sorted
 *         increasingly; clusters sorted by size, largest first, ties by their smallest index.
 *         Empty when no cluster qualifies. Each PointIndices carries cloud.header.
 * \throws std::invalid_argument when \a params is invalid or an index is out of range.
 *
 * \code
 * const auto clusters = pcl::icf::segmentation::extractClusters(scene, above.indices, {});
 * \endcode
 */
template <typename PointT>
std::vector<pcl::PointIndices> extractClusters(const pcl::PointCloud<PointT>& cloud,
                                               const pcl::Indices& indices,
                                               const ClusterParams& params);

/** \brief Sorts \a clusters into extractClusters' order: each cluster's indices increasing, then
 * the clusters by size (largest first), ties by smallest index. */
void sortClusters(std::vector<pcl::PointIndices>& clusters);

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl

// The templates above are compiled into pcl_icf_segmentation for
// PCL_ICF_SEGMENTATION_POINT_TYPES (precompiled_point_types.h: other point types, how); their
// bodies are in the library's sources (src/impl/euclidean_clusters.hpp), not installed.
