/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The point types pcl_icf_segmentation is compiled for.
 *
 * The templated stages (voxelDownsample, findTablePlane, refineTablePlane, planeInliers,
 * tableHull, aboveTableIndices, extractClusters, segmentTabletop), and localizeObject and
 * ObjectTracker::track above them, are explicitly instantiated for these types in the
 * libraries' sources (PCL's PCL_INSTANTIATE pattern), so a user's translation unit compiles no
 * algorithm. Their bodies and helpers live in the sources (src/impl/), not in the installed
 * headers: the headers hold the API only, and the types below are the ones supported, whether
 * or not PCL_NO_PRECOMPILE is defined.
 *
 * Another point type: the stages read x, y, z only (and carry r, g, b through the voxel grid
 * and the hull), so copy the cloud into one of these first, e.g.
 * `pcl::copyPointCloud(custom, xyz)` with a pcl::PointCloud<pcl::PointXYZ> xyz (indices into
 * the copy are indices into the original), or add the type to this list and rebuild the
 * library.
 */
#define PCL_ICF_SEGMENTATION_POINT_TYPES (pcl::PointXYZ)(pcl::PointXYZRGB)(pcl::PointXYZRGBA)
