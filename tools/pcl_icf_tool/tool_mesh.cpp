/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "tool_mesh.h"

#include "tool_output.h"

#include <pcl/conversions.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstring>
#include <limits>

namespace pcl_icf_tool {

namespace {

/** x, y, z of vertex \a i of a mesh's cloud (FLOAT32 or FLOAT64 fields). */
Eigen::Vector3d vertex(const pcl::PCLPointCloud2& cloud, const int offsets[3],
                       const bool doubles[3], std::size_t i) {
  Eigen::Vector3d v;
  const std::uint8_t* p = cloud.data.data() + i * cloud.point_step;
  for (int k = 0; k < 3; ++k) {
    if (doubles[k]) {
      double d;
      std::memcpy(&d, p + offsets[k], sizeof d);
      v[k] = d;
    } else {
      float f;
      std::memcpy(&f, p + offsets[k], sizeof f);
      v[k] = f;
    }
  }
  return v;
}

bool xyzLayout(const pcl::PCLPointCloud2& cloud, int offsets[3], bool doubles[3]) {
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    offsets[k] = -1;
    for (const auto& f : cloud.fields)
      if (f.name == names[k] && (f.datatype == pcl::PCLPointField::FLOAT32 ||
                                 f.datatype == pcl::PCLPointField::FLOAT64)) {
        offsets[k] = static_cast<int>(f.offset);
        doubles[k] = f.datatype == pcl::PCLPointField::FLOAT64;
      }
    if (offsets[k] < 0)
      return false;
  }
  const std::size_t n = static_cast<std::size_t>(cloud.width) * cloud.height;
  return cloud.data.size() >= n * cloud.point_step;
}

}  // namespace

pcl::PolygonMesh posedMesh(const pcl::PolygonMesh& mesh, const Eigen::Matrix4d& pose,
                           double scale) {
  int offsets[3];
  bool doubles[3];
  if (!xyzLayout(mesh.cloud, offsets, doubles))
    throw OutputError("the mesh has no float x, y, z vertex fields");
  const std::size_t n = static_cast<std::size_t>(mesh.cloud.width) * mesh.cloud.height;
  pcl::PointCloud<pcl::PointXYZ> vertices;
  vertices.resize(n);
  const Eigen::Matrix3d r = pose.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = pose.topRightCorner<3, 1>();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d v = r * (scale * vertex(mesh.cloud, offsets, doubles, i)) + t;
    vertices[i].getVector3fMap() = v.cast<float>();
  }
  pcl::PolygonMesh out;
  pcl::toPCLPointCloud2(vertices, out.cloud);
  out.polygons = mesh.polygons;
  return out;
}

double meshExtent(const pcl::PolygonMesh& mesh) {
  int offsets[3];
  bool doubles[3];
  if (!xyzLayout(mesh.cloud, offsets, doubles))
    return 0.0;
  const std::size_t n = static_cast<std::size_t>(mesh.cloud.width) * mesh.cloud.height;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  bool any = false;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d v = vertex(mesh.cloud, offsets, doubles, i);
    if (!v.allFinite())
      continue;
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
    any = true;
  }
  return any ? (hi - lo).norm() : 0.0;
}

}  // namespace pcl_icf_tool
