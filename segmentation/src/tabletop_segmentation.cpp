/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Explicit instantiation for PCL_ICF_SEGMENTATION_POINT_TYPES (PCL's PCL_INSTANTIATE pattern).
#include <pcl/icf/segmentation/tabletop_segmentation.h>

#include <pcl/point_types.h>
#include <pcl/impl/instantiate.hpp>

#include "impl/tabletop_segmentation.hpp"

PCL_INSTANTIATE(IcfSegmentTabletop, PCL_ICF_SEGMENTATION_POINT_TYPES)
