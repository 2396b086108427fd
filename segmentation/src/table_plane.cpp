/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Explicit instantiation for PCL_ICF_SEGMENTATION_POINT_TYPES (PCL's PCL_INSTANTIATE pattern).
#include <pcl/icf/segmentation/table_plane.h>

#include <pcl/point_types.h>
#include <pcl/impl/instantiate.hpp>

#include "impl/table_plane.hpp"

PCL_INSTANTIATE(IcfFindTablePlane, PCL_ICF_SEGMENTATION_POINT_TYPES)
PCL_INSTANTIATE(IcfPlaneInliers, PCL_ICF_SEGMENTATION_POINT_TYPES)
PCL_INSTANTIATE(IcfRefineTablePlane, PCL_ICF_SEGMENTATION_POINT_TYPES)
