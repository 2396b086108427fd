/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <pcl/PolygonMesh.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace pcl_icf_python {

namespace py = pybind11;

/** \brief Fills a PCL cloud from \a xyz, shape (N, 3) (unorganized) or (H, W, 3) (organized,
 * W x H), float32 or float64, any strides (a view is read as it is, never copied first), and the
 * optional \a rgb, uint8 of the same leading shape with 3 channels (white without it).
 * \throws py::value_error naming \a name / \a rgb_name for a wrong shape or dtype, no points, or
 * no finite point. */
pcl::PointCloud<pcl::PointXYZRGBA> sceneCloud(const py::array& xyz, const py::object& rgb,
                                              const std::string& name, const std::string& rgb_name);

/** \brief The finite points of \a xyz, shape (N, 3) or (H, W, 3), float32 or float64.
 * \throws py::value_error naming \a name as sceneCloud. */
std::vector<Eigen::Vector3f> finitePoints(const py::array& xyz, const std::string& name);

/** \brief A mesh from \a vertices (V, 3) float and \a faces (F, k >= 3) integer indices in
 * [0, V). \throws py::value_error naming the array for a wrong shape, dtype, a non-finite vertex
 * or an index out of range. */
pcl::PolygonMesh polygonMesh(const py::array& vertices, const py::array& faces);

/** \brief A finite rigid 4x4 matrix (numbers, any dtype convertible to float64). \throws
 * py::value_error naming \a name otherwise. */
Eigen::Isometry3f rigidPose(const py::handle& matrix, const std::string& name);

/** \brief A 4x4 float64 numpy array holding \a m. */
py::array_t<double> matrixArray(const Eigen::Matrix4d& m);

}  // namespace pcl_icf_python
