/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Explicit instantiation for PCL_ICF_SEGMENTATION_POINT_TYPES (PCL's PCL_INSTANTIATE pattern).
#include <pcl/icf/segmentation/above_table.h>

#include <pcl/point_types.h>
#include <pcl/impl/instantiate.hpp>

#include "impl/above_table.hpp"

PCL_INSTANTIATE(IcfTableHull, PCL_ICF_SEGMENTATION_POINT_TYPES)
PCL_INSTANTIATE(IcfAboveTableIndices, PCL_ICF_SEGMENTATION_POINT_TYPES)
