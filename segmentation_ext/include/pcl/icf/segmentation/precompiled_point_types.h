/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The point types for which pcl_icf_segmentation ships compiled templates.
 *
 * The templated stages (voxelDownsample, findTablePlane, planeInliers, tableHull,
 * aboveTableIndices, extractClusters, segmentTabletop) are explicitly instantiated for these types
 * in the library's sources, following PCL's PCL_INSTANTIATE pattern. For any other point type with
 * x, y, z, define PCL_NO_PRECOMPILE before including the headers (the headers then include their
 * impl/ files) or include the impl/ .hpp files directly.
 */
#define PCL_ICF_SEGMENTATION_POINT_TYPES (pcl::PointXYZ)(pcl::PointXYZRGB)(pcl::PointXYZRGBA)
