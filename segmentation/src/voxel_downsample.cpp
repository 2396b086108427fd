/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Explicit instantiation for PCL_ICF_SEGMENTATION_POINT_TYPES (PCL's PCL_INSTANTIATE pattern).
#include <pcl/icf/segmentation/voxel_downsample.h>

#include <pcl/point_types.h>
#include <pcl/impl/instantiate.hpp>

#include "impl/voxel_downsample.hpp"

PCL_INSTANTIATE(IcfVoxelDownsample, PCL_ICF_SEGMENTATION_POINT_TYPES)
