/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "arrays.h"

#include <pcl/conversions.h>
#include <pcl/icf/registration/rigid_transform.h>

#include <cmath>
#include <cstdint>
#include <cstring>

namespace pcl_icf_python {

namespace {

/** Shape of a point array: rows x cols points (rows = 1 for (N, 3)). */
struct PointGrid {
  py::ssize_t rows = 1;
  py::ssize_t cols = 0;
  py::ssize_t row_stride = 0;  ///< bytes
  py::ssize_t col_stride = 0;  ///< bytes
  py::ssize_t coord_stride = 0;
  bool doubles = false;
};

std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d)
    s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

PointGrid pointGrid(const py::array& xyz, const std::string& name) {
  const char kind = xyz.dtype().kind();
  if (kind != 'f' || (xyz.itemsize() != 4 && xyz.itemsize() != 8))
    throw py::value_error(name + ": dtype " + py::str(xyz.dtype()).cast<std::string>() +
                          ", expected float32 or float64");
  PointGrid g;
  g.doubles = xyz.itemsize() == 8;
  if (xyz.ndim() == 2 && xyz.shape(1) == 3) {
    g.cols = xyz.shape(0);
    g.col_stride = xyz.strides(0);
    g.coord_stride = xyz.strides(1);
  } else if (xyz.ndim() == 3 && xyz.shape(2) == 3) {
    g.rows = xyz.shape(0);
    g.cols = xyz.shape(1);
    g.row_stride = xyz.strides(0);
    g.col_stride = xyz.strides(1);
    g.coord_stride = xyz.strides(2);
  } else {
    throw py::value_error(name + ": shape " + shapeText(xyz) + ", expected (N, 3) or (H, W, 3)");
  }
  if (g.rows * g.cols == 0)
    throw py::value_error(name + ": no points (shape " + shapeText(xyz) + ")");
  return g;
}

float coordinate(const std::uint8_t* p, bool doubles) {
  if (doubles) {
    double d;
    std::memcpy(&d, p, sizeof d);
    return static_cast<float>(d);
  }
  float f;
  std::memcpy(&f, p, sizeof f);
  return f;
}

Eigen::Vector3f pointAt(const std::uint8_t* base, const PointGrid& g, py::ssize_t r,
                        py::ssize_t c) {
  const std::uint8_t* p = base + r * g.row_stride + c * g.col_stride;
  return {coordinate(p, g.doubles), coordinate(p + g.coord_stride, g.doubles),
          coordinate(p + 2 * g.coord_stride, g.doubles)};
}

void requireFinitePoint(bool any, const std::string& name) {
  if (!any)
    throw py::value_error(name +
                          ": no finite point (every point has a NaN or infinite "
                          "coordinate)");
}

}  // namespace

pcl::PointCloud<pcl::PointXYZRGBA> sceneCloud(const py::array& xyz, const py::object& rgb,
                                              const std::string& name,
                                              const std::string& rgb_name) {
  const PointGrid g = pointGrid(xyz, name);
  const auto* base = static_cast<const std::uint8_t*>(xyz.data());
  const std::uint8_t* colour = nullptr;
  py::ssize_t c_row = 0, c_col = 0, c_chan = 0;
  py::array colours;
  if (!rgb.is_none()) {
    if (!py::isinstance<py::array>(rgb))
      throw py::value_error(rgb_name + ": expected a numpy array of uint8, got " +
                            py::str(rgb.get_type()).cast<std::string>());
    colours = rgb.cast<py::array>();
    if (!py::isinstance<py::array_t<std::uint8_t>>(colours) || colours.dtype().kind() != 'u')
      throw py::value_error(rgb_name + ": dtype " + py::str(colours.dtype()).cast<std::string>() +
                            ", expected uint8");
    if (colours.ndim() != xyz.ndim() || colours.shape(colours.ndim() - 1) != 3 ||
        colours.shape(0) != xyz.shape(0) || (xyz.ndim() == 3 && colours.shape(1) != xyz.shape(1)))
      throw py::value_error(rgb_name + ": shape " + shapeText(colours) + ", expected " +
                            shapeText(xyz) + " like " + name);
    colour = static_cast<const std::uint8_t*>(colours.data());
    if (xyz.ndim() == 3) {
      c_row = colours.strides(0);
      c_col = colours.strides(1);
      c_chan = colours.strides(2);
    } else {
      c_col = colours.strides(0);
      c_chan = colours.strides(1);
    }
  }
  pcl::PointCloud<pcl::PointXYZRGBA> cloud;
  cloud.resize(static_cast<std::size_t>(g.rows * g.cols));
  cloud.width = static_cast<std::uint32_t>(g.cols);
  cloud.height = static_cast<std::uint32_t>(g.rows);
  bool any_finite = false;
  bool dense = true;
  std::size_t i = 0;
  for (py::ssize_t r = 0; r < g.rows; ++r)
    for (py::ssize_t c = 0; c < g.cols; ++c, ++i) {
      auto& q = cloud[i];
      q.getVector3fMap() = pointAt(base, g, r, c);
      const bool finite = std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
      any_finite = any_finite || finite;
      dense = dense && finite;
      if (colour) {
        const std::uint8_t* p = colour + r * c_row + c * c_col;
        q.r = p[0];
        q.g = p[c_chan];
        q.b = p[2 * c_chan];
        q.a = 255;
      } else {
        q.r = q.g = q.b = q.a = 255;
      }
    }
  requireFinitePoint(any_finite, name);
  cloud.is_dense = dense;
  return cloud;
}

std::vector<Eigen::Vector3f> finitePoints(const py::array& xyz, const std::string& name) {
  const PointGrid g = pointGrid(xyz, name);
  const auto* base = static_cast<const std::uint8_t*>(xyz.data());
  std::vector<Eigen::Vector3f> points;
  points.reserve(static_cast<std::size_t>(g.rows * g.cols));
  for (py::ssize_t r = 0; r < g.rows; ++r)
    for (py::ssize_t c = 0; c < g.cols; ++c) {
      const Eigen::Vector3f p = pointAt(base, g, r, c);
      if (p.allFinite())
        points.push_back(p);
    }
  requireFinitePoint(!points.empty(), name);
  return points;
}

pcl::PolygonMesh polygonMesh(const py::array& vertices, const py::array& faces) {
  if (vertices.ndim() != 2)
    throw py::value_error("vertices: shape " + shapeText(vertices) + ", expected (V, 3)");
  const std::vector<Eigen::Vector3f> points = [&] {
    const PointGrid g = pointGrid(vertices, "vertices");
    const auto* base = static_cast<const std::uint8_t*>(vertices.data());
    std::vector<Eigen::Vector3f> v(static_cast<std::size_t>(g.cols));
    for (py::ssize_t c = 0; c < g.cols; ++c) {
      v[static_cast<std::size_t>(c)] = pointAt(base, g, 0, c);
      if (!v[static_cast<std::size_t>(c)].allFinite())
        throw py::value_error("vertices: row " + std::to_string(c) + " is not finite");
    }
    return v;
  }();
  const char kind = faces.dtype().kind();
  if (kind != 'i' && kind != 'u')
    throw py::value_error("faces: dtype " + py::str(faces.dtype()).cast<std::string>() +
                          ", expected an integer type");
  if (faces.ndim() != 2 || faces.shape(1) < 3)
    throw py::value_error("faces: shape " + shapeText(faces) + ", expected (F, 3) or (F, k >= 3)");
  if (faces.shape(0) == 0)
    throw py::value_error("faces: no faces (shape " + shapeText(faces) + ")");
  const auto ids = py::array_t<std::int64_t, py::array::forcecast>(faces);
  const auto view = ids.unchecked<2>();
  pcl::PolygonMesh mesh;
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    cloud[i].getVector3fMap() = points[i];
  pcl::toPCLPointCloud2(cloud, mesh.cloud);
  mesh.polygons.resize(static_cast<std::size_t>(view.shape(0)));
  const auto count = static_cast<std::int64_t>(points.size());
  for (py::ssize_t f = 0; f < view.shape(0); ++f) {
    auto& polygon = mesh.polygons[static_cast<std::size_t>(f)].vertices;
    for (py::ssize_t k = 0; k < view.shape(1); ++k) {
      const std::int64_t id = view(f, k);
      if (id < 0 || id >= count)
        throw py::value_error("faces: row " + std::to_string(f) + " refers to vertex " +
                              std::to_string(id) + ", not in [0, " + std::to_string(count) + ")");
      polygon.push_back(static_cast<std::uint32_t>(id));
    }
  }
  return mesh;
}

Eigen::Isometry3f rigidPose(const py::handle& matrix, const std::string& name) {
  py::array_t<double, py::array::forcecast> m;
  try {
    m = py::array_t<double, py::array::forcecast>::ensure(matrix);
  } catch (const py::error_already_set&) {
  }
  if (!m || m.ndim() != 2 || m.shape(0) != 4 || m.shape(1) != 4)
    throw py::value_error(name + ": expected a 4x4 matrix (a rigid pose)");
  const auto v = m.unchecked<2>();
  Eigen::Matrix4d pose;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      pose(r, c) = v(r, c);
  try {
    pcl::icf::validateRigidTransform(pose, name);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  Eigen::Isometry3f out = Eigen::Isometry3f::Identity();
  out.matrix() = pose.cast<float>();
  return out;
}

py::array_t<double> matrixArray(const Eigen::Matrix4d& m) {
  py::array_t<double> a({4, 4});
  auto v = a.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      v(r, c) = m(r, c);
  return a;
}

}  // namespace pcl_icf_python
