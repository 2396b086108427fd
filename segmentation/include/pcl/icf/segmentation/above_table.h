/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/segmentation/precompiled_point_types.h>
#include <pcl/icf/segmentation/table_plane.h>
#include <pcl/point_cloud.h>
#include <pcl/types.h>

#include <Eigen/Core>

#include <cstddef>
#include <string>

namespace pcl {
namespace icf {
namespace segmentation {

/** \brief Parameters of the objects-above-the-table stage (a prism over the table's hull). */
struct AboveTableParams {
  /** Lowest signed height above the table plane of an object point, in scene units (metres).
   * Points lower than this (the table itself, its noise) are dropped. Must be finite and
   * < max_height. Default 0.004 (4 mm): tuned on the PCL milk scene, whose reference cut
   * milk.pcd starts 4.1 mm above the least-squares floor plane (5 mm loses 44 of its 13,704
   * points, 4 mm none); Kinect depth noise on a table at 1 m is 2-3 mm. */
  double min_height = 0.004;
  /** Highest signed height above the table plane of an object point, in scene units (metres).
   * Must be finite. Default 0.5. */
  double max_height = 0.5;

  /** \brief Throws std::invalid_argument naming the field and its value when a field is out of
   * range. */
  void validate() const;
};

/** \brief Outcome of aboveTableIndices. */
enum class AboveTableStatus {
  Ok,             ///< the prism was evaluated (indices may still be empty: nothing on the table)
  NoPlane,        ///< the plane given was not found (TablePlane::status != Found)
  DegenerateHull  ///< the table inliers have no 2D convex hull (fewer than 3, or collinear)
};

/** \brief "Ok", "NoPlane" or "DegenerateHull". */
std::string toString(AboveTableStatus status);

/** \brief The points above the table and the hull they were tested against. */
struct AboveTable {
  AboveTableStatus status = AboveTableStatus::NoPlane;
  /** Indices (into the cloud given) of the points inside the prism, in the order of the given
   * indices. */
  pcl::Indices indices;
  /** Number of vertices of the table's 2D convex hull the prism stands on (0 when none). */
  std::size_t hull_size = 0;
};

/** \brief The 2D convex hull (pcl::ConvexHull, dimension 2) of \a cloud[inliers] projected onto
 * the plane \a coefficients (a unit normal and offset, as in TablePlane).
 *
 * \return the hull's vertices on the plane, in order; empty when fewer than 3 finite inliers or
 *         when they are collinear (checked before qhull runs, so PCL logs nothing).
 * \throws std::invalid_argument when an index is out of range.
 */
template <typename PointT>
pcl::PointCloud<PointT> tableHull(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& inliers,
                                  const Eigen::Vector4f& coefficients);

/** \brief Points of \a cloud[indices] inside the prism that stands on the polygon \a hull, from
 * params.min_height to params.max_height above its plane (pcl::ExtractPolygonalPrismData).
 *
 * ExtractPolygonalPrismData refits the plane to the hull's vertices and orients it towards
 * cloud.sensor_origin_, so heights are positive on the sensor's side of the table.
 *
 * \param[in] cloud  read only during the call.
 * \param[in] indices  candidate points (each < cloud.size()); non-finite ones are skipped.
 * \param[in] hull  a planar convex polygon with at least 3 vertices (as from tableHull); it may
 *            come from another cloud in the same frame, e.g. a voxel-downsampled copy.
 * \param[in] params  see AboveTableParams.
 * \return status Ok and the indices inside the prism, or DegenerateHull (hull with < 3
 *         vertices) and no indices.
 * \throws std::invalid_argument when \a params is invalid or an index is out of range.
 */
template <typename PointT>
AboveTable aboveTableIndices(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
                             const pcl::PointCloud<PointT>& hull, const AboveTableParams& params);

/** \brief Points of \a cloud[indices] above the table \a plane: tableHull of plane.inliers,
 * then the prism of the overload above.
 *
 * \param[in] plane  a result of findTablePlane on the same \a cloud (its inliers index
 *            \a cloud). Status NoPlane unless plane.found().
 *
 * \code
 * const auto finite = finiteIndices(scene);
 * const auto plane = findTablePlane(scene, finite, {});
 * const auto above = aboveTableIndices(scene, finite, plane, {});
 * \endcode
 */
template <typename PointT>
AboveTable aboveTableIndices(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
                             const TablePlane& plane, const AboveTableParams& params);

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl

// The templates above are compiled into pcl_icf_segmentation for
// PCL_ICF_SEGMENTATION_POINT_TYPES (precompiled_point_types.h: other point types, how); their
// bodies are in the library's sources (src/impl/above_table.hpp), not installed.
