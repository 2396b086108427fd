/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief pcl_icf_tool's mesh geometry: the model moved to a found pose (for --output and the
 * pictures) and its size (for the units' guess). */

#include <pcl/PolygonMesh.h>

#include <Eigen/Core>

namespace pcl_icf_tool {

/** \brief The mesh's vertices scaled by \a scale and then moved by \a pose (x' = R s x + t),
 * with its polygons: a plain xyz mesh. \throws OutputError when the mesh has no float x, y,
 * z vertex fields. */
pcl::PolygonMesh posedMesh(const pcl::PolygonMesh& mesh, const Eigen::Matrix4d& pose, double scale);

/** \brief Bounding-box diagonal of the mesh's vertices (0 when it has none). */
double meshExtent(const pcl::PolygonMesh& mesh);

}  // namespace pcl_icf_tool
