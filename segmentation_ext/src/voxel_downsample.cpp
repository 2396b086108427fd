/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Explicit instantiation for PCL_ICF_SEGMENTATION_POINT_TYPES (PCL's PCL_INSTANTIATE pattern).
#include <pcl/icf/segmentation/voxel_downsample.h>

#ifndef PCL_NO_PRECOMPILE
#include <pcl/point_types.h>
#include <pcl/icf/segmentation/impl/voxel_downsample.hpp>
#include <pcl/impl/instantiate.hpp>

PCL_INSTANTIATE(IcfVoxelDownsample, PCL_ICF_SEGMENTATION_POINT_TYPES)
#endif  // PCL_NO_PRECOMPILE
