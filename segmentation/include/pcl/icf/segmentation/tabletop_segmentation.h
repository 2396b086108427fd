/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/PointIndices.h>
#include <pcl/icf/segmentation/above_table.h>
#include <pcl/icf/segmentation/euclidean_clusters.h>
#include <pcl/icf/segmentation/finite_indices.h>
#include <pcl/icf/segmentation/precompiled_point_types.h>
#include <pcl/icf/segmentation/table_plane.h>
#include <pcl/icf/segmentation/voxel_downsample.h>
#include <pcl/point_cloud.h>
#include <pcl/types.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace pcl {
namespace icf {
namespace segmentation {

/** \brief Parameters of the whole table-top segmentation; every length in scene units, which
 * the defaults assume are metres. */
struct TabletopParams {
  /** Downsampling of the finite points before the plane search: RANSAC runs on the voxel
   * centroids, the plane is then refitted to its inliers in the full cloud (refineTablePlane) and
   * the table's hull is taken from the centroid inliers. Above-table selection and clustering
   * always run at full resolution. 0 searches the plane in the full cloud (2-4x slower on a
   * 640x480 scene). Default voxel_size 0.01 (1 cm). */
  VoxelParams voxel{0.01};
  /** The table plane. min_inliers counts inliers among the voxel centroids when voxel_size > 0.
   * Defaults as in TablePlaneParams. */
  TablePlaneParams plane;
  /** The prism above the table's hull. Defaults as in AboveTableParams. */
  AboveTableParams above_table;
  /** The clustering of the points above the table. Defaults as in ClusterParams. */
  ClusterParams cluster;
  /** Units check: when the extent of the finite points (robustExtent: the diagonal of the box
   * between their 1st and 99th percentile on each axis, so that stray returns do not count)
   * exceeds this
   * (scene units), the scene is taken to be in millimetres while the parameters are in metres, and
   * the segmentation stops with status SceneUnitsSuspect. A Kinect-type scene in metres spans a few
   * metres; the same scene in millimetres spans thousands. 0 turns the check off. Must be
   * finite and >= 0. Default 50. */
  double max_scene_extent = 50.0;
  /** Units check for organized clouds: when the median distance between horizontally adjacent
   * finite pixels exceeds max_pixel_spacing_factor * cluster.tolerance, clustering could not link
   * neighbouring pixels (a metre-scale Kinect scene has a few millimetres between pixels, the
   * same scene in millimetres a few units); status SceneUnitsSuspect. 0 turns the check off.
   * Must be finite and >= 0. Default 10. */
  double max_pixel_spacing_factor = 10.0;

  /** \brief Validates every stage's parameters and the fields above; throws
   * std::invalid_argument naming the field (e.g. "plane.distance_threshold") and its value. */
  void validate() const;
};

/** \brief Outcome of segmentTabletop, first failing stage wins. */
enum class TabletopStatus {
  Ok,                 ///< table found and at least one cluster above it
  EmptyCloud,         ///< the cloud has no points
  NoFinitePoints,     ///< every point has a NaN/Inf coordinate
  TooFewPoints,       ///< fewer finite points than plane.min_inliers: no table can be accepted
  SceneUnitsSuspect,  ///< the scene looks like millimetres with metre parameters (see message)
  NoPlane,            ///< no plane with plane.min_inliers inliers (see plane.status), or no hull
  NoCluster           ///< a table, but no cluster of cluster.min_size points above it
};

/** \brief The enumerator's name, e.g. "SceneUnitsSuspect". */
std::string toString(TabletopStatus status);

/** \brief Wall-clock time of each stage of segmentTabletop, in milliseconds (steady_clock). A
 * stage that did not run reports 0. */
struct TabletopTimings {
  double finite_ms = 0.0;       ///< finiteIndices and the units checks
  double voxel_ms = 0.0;        ///< voxelDownsample
  double plane_ms = 0.0;        ///< findTablePlane, and refineTablePlane on the full cloud
  double above_table_ms = 0.0;  ///< tableHull and aboveTableIndices
  double cluster_ms = 0.0;      ///< extractClusters
  double total_ms = 0.0;        ///< the whole call, validation included
};

/** \brief Result of segmentTabletop. Every index refers to the input cloud. */
struct TabletopSegmentation {
  TabletopStatus status = TabletopStatus::EmptyCloud;
  /** Empty when status is Ok; otherwise a one-line explanation with the numbers that decided
   * it (also logged with PCL_WARN for SceneUnitsSuspect). */
  std::string message;
  /** The table: coefficients oriented towards cloud.sensor_origin_ and its inliers among the
   * finite points of the full-resolution cloud (refitted and reselected there when
   * voxel_size > 0). Status NoPlane (all zero) when the segmentation stopped before the plane. */
  TablePlane plane;
  /** The table's convex hull on its plane: its vertices in order, in the cloud's frame (empty
   * when the segmentation stopped before it). What the objects stand on extends this far. */
  std::vector<Eigen::Vector3f> hull;
  /** Finite points inside the prism over the table's convex hull, increasing. */
  pcl::Indices above_table;
  /** Clusters of above_table, in extractClusters' order (largest first). */
  std::vector<pcl::PointIndices> clusters;
  /** Number of finite points in the input. */
  std::size_t finite_points = 0;
  /** Points the plane was searched in (the voxel centroids, or the finite points). */
  std::size_t plane_search_points = 0;
  TabletopTimings timing;
};

/** \brief Table-top segmentation of one scene: finite points -> optional voxel grid -> seeded
 * RANSAC table plane (refitted at full resolution) -> points in the prism over the table's convex
 * hull -> Euclidean clusters.
 *
 * Each stage is also available on its own (finiteIndices, voxelDownsample, findTablePlane,
 * refineTablePlane, planeInliers, tableHull, aboveTableIndices, extractClusters). Deterministic:
 * the same cloud and parameters give the same result. Re-entrant: no shared state; the cloud is
 * only read.
 *
 * Bad data (empty, all-NaN, a handful of points, no plane, nothing on the table, millimetre
 * units) gives a status, never an exception; only invalid \a params throw.
 *
 * \param[in] cloud  a scene in metres, organized (Kinect, with NaNs) or not; sensor_origin_ is
 *            the viewpoint that orients the table normal (the camera frame's origin by default).
 * \param[in] params  see TabletopParams; defaults are tuned on the PCL milk scene and mOSD.
 * \throws std::invalid_argument when \a params is invalid.
 *
 * \code
 * pcl::PointCloud<pcl::PointXYZRGBA> scene;
 * pcl::io::loadPCDFile("milk_cartoon_all_small_clorox.pcd", scene);
 * const auto seg = pcl::icf::segmentation::segmentTabletop(scene);
 * if (seg.status == pcl::icf::segmentation::TabletopStatus::Ok)
 *   for (const pcl::PointIndices& object : seg.clusters) { ... }
 * \endcode
 */
template <typename PointT>
TabletopSegmentation segmentTabletop(const pcl::PointCloud<PointT>& cloud,
                                     const TabletopParams& params = {});

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl

// The templates above are compiled into pcl_icf_segmentation for
// PCL_ICF_SEGMENTATION_POINT_TYPES (precompiled_point_types.h: other point types, how); their
// bodies are in the library's sources (src/impl/tabletop_segmentation.hpp), not installed.
