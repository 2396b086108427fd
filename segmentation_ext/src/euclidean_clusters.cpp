/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Explicit instantiation for PCL_ICF_SEGMENTATION_POINT_TYPES (PCL's PCL_INSTANTIATE pattern).
#include <pcl/icf/segmentation/euclidean_clusters.h>

#ifndef PCL_NO_PRECOMPILE
#include <pcl/point_types.h>
#include <pcl/icf/segmentation/impl/euclidean_clusters.hpp>
#include <pcl/impl/instantiate.hpp>

PCL_INSTANTIATE(IcfExtractClusters, PCL_ICF_SEGMENTATION_POINT_TYPES)
#endif  // PCL_NO_PRECOMPILE
