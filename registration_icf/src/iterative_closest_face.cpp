/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Pre-instantiation for the common point types, so users do not compile the class.
#include <pcl/icf/impl/iterative_closest_face.hpp>

template class pcl::IterativeClosestFace<pcl::PointXYZ, float>;
template class pcl::IterativeClosestFace<pcl::PointXYZRGB, float>;
template class pcl::IterativeClosestFace<pcl::PointXYZRGBA, float>;
template class pcl::IterativeClosestFace<pcl::PointNormal, float>;
template class pcl::IterativeClosestFace<pcl::PointXYZ, double>;
