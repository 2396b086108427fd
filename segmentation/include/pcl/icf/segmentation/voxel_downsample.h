/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/segmentation/precompiled_point_types.h>
#include <pcl/point_cloud.h>
#include <pcl/types.h>

namespace pcl {
namespace icf {
namespace segmentation {

/** \brief Parameters of the optional voxel-grid downsampling stage. */
struct VoxelParams {
  /** Edge length of the cubic voxels, in scene units (metres). 0 turns downsampling off (the
   * stage then copies the indexed points). Must be finite and >= 0. Default 0. */
  double voxel_size = 0.0;

  /** \brief Throws std::invalid_argument naming the field and its value when a field is out of
   * range. */
  void validate() const;
};

/** \brief The points \a cloud[indices] replaced by the centroid of each occupied voxel
 * (pcl::VoxelGrid), or copied unchanged when \a params.voxel_size is 0.
 *
 * \param[in] cloud  any cloud, organized or not; read only during the call.
 * \param[in] indices  the points to use; each must be < cloud.size(). Non-finite points among
 *            them are skipped.
 * \param[in] params  see VoxelParams.
 * \return an unorganized, dense cloud (height 1) with the header, sensor origin and orientation
 *         of \a cloud; its point order is deterministic (VoxelGrid sorts by voxel index). When the
 *         points span more voxels than VoxelGrid can index (2^31: a tiny voxel, or a stray point
 *         far away), a warning is logged and the indexed finite points are returned unchanged
 *         (PCL's VoxelGrid would return its whole input, NaN points included).
 * \throws std::invalid_argument when \a params is invalid or an index is out of range.
 *
 * \code
 * pcl::icf::segmentation::VoxelParams vp;
 * vp.voxel_size = 0.01;  // 1 cm
 * const auto small = pcl::icf::segmentation::voxelDownsample(scene, finiteIndices(scene), vp);
 * \endcode
 */
template <typename PointT>
pcl::PointCloud<PointT> voxelDownsample(const pcl::PointCloud<PointT>& cloud,
                                        const pcl::Indices& indices, const VoxelParams& params);

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl

// The templates above are compiled into pcl_icf_segmentation for
// PCL_ICF_SEGMENTATION_POINT_TYPES (precompiled_point_types.h: other point types, how); their
// bodies are in the library's sources (src/impl/voxel_downsample.hpp), not installed.
