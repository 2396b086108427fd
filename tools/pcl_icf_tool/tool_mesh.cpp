/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "tool_mesh.h"

#include "tool_output.h"

#include <pcl_icf_internal/point_field.h>

#include <pcl/conversions.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <limits>

namespace pcl_icf_tool {

namespace {

/** Where x, y and z lie in each vertex of a mesh's cloud: any numeric field type (PLY files
 * carry float, double and integer coordinates), read with the libraries' one field reader. */
struct VertexLayout {
  const pcl::PCLPointField* axes[3] = {nullptr, nullptr, nullptr};

  /** x, y, z of vertex \a i. */
  Eigen::Vector3d at(const pcl::PCLPointCloud2& cloud, std::size_t i) const {
    const std::uint8_t* p = cloud.data.data() + i * cloud.point_step;
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k)
      v[k] = pcl::icf::internal::readFieldValue(p + axes[k]->offset, axes[k]->datatype);
    return v;
  }
};

/** The layout of \a cloud's x, y, z fields (the ones FaceMesh reads:
 * pcl::icf::internal::findVertexFields); false when one is unusable or the data is shorter than
 * its vertices need. */
bool vertexLayout(const pcl::PCLPointCloud2& cloud, VertexLayout& layout) {
  if (!pcl::icf::internal::findVertexFields(cloud, layout.axes).empty())
    return false;
  const std::size_t n = static_cast<std::size_t>(cloud.width) * cloud.height;
  return cloud.data.size() >= n * cloud.point_step;
}

}  // namespace

pcl::PolygonMesh posedMesh(const pcl::PolygonMesh& mesh, const Eigen::Matrix4d& pose,
                           double scale) {
  VertexLayout layout;
  if (!vertexLayout(mesh.cloud, layout))
    throw OutputError("the mesh has no numeric x, y, z vertex fields");
  const std::size_t n = static_cast<std::size_t>(mesh.cloud.width) * mesh.cloud.height;
  pcl::PointCloud<pcl::PointXYZ> vertices;
  vertices.resize(n);
  const Eigen::Matrix3d r = pose.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = pose.topRightCorner<3, 1>();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d v = r * (scale * layout.at(mesh.cloud, i)) + t;
    vertices[i].getVector3fMap() = v.cast<float>();
  }
  pcl::PolygonMesh out;
  pcl::toPCLPointCloud2(vertices, out.cloud);
  out.polygons = mesh.polygons;
  return out;
}

double meshExtent(const pcl::PolygonMesh& mesh) {
  VertexLayout layout;
  if (!vertexLayout(mesh.cloud, layout))
    return 0.0;
  const std::size_t n = static_cast<std::size_t>(mesh.cloud.width) * mesh.cloud.height;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  bool any = false;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d v = layout.at(mesh.cloud, i);
    if (!v.allFinite())
      continue;
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
    any = true;
  }
  return any ? (hi - lo).norm() : 0.0;
}

}  // namespace pcl_icf_tool
