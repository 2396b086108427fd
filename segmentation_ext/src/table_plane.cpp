/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Explicit instantiation for PCL_ICF_SEGMENTATION_POINT_TYPES (PCL's PCL_INSTANTIATE pattern).
#include <pcl/icf/segmentation/table_plane.h>

#ifndef PCL_NO_PRECOMPILE
#include <pcl/point_types.h>
#include <pcl/icf/segmentation/impl/table_plane.hpp>
#include <pcl/impl/instantiate.hpp>

PCL_INSTANTIATE(IcfFindTablePlane, PCL_ICF_SEGMENTATION_POINT_TYPES)
PCL_INSTANTIATE(IcfPlaneInliers, PCL_ICF_SEGMENTATION_POINT_TYPES)
PCL_INSTANTIATE(IcfRefineTablePlane, PCL_ICF_SEGMENTATION_POINT_TYPES)
#endif  // PCL_NO_PRECOMPILE
