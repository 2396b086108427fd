#include "synthetic/mesh_geometry.h"

#include <pcl/conversions.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {
namespace synthetic {

pcl::PolygonMesh meshOf(const std::vector<Eigen::Vector3f>& vertices,
                        const std::vector<Face>& faces) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.reserve(vertices.size());
  for (const auto& v : vertices)
    cloud.push_back(pcl::PointXYZ(v.x(), v.y(), v.z()));
  pcl::PolygonMesh mesh;
  pcl::toPCLPointCloud2(cloud, mesh.cloud);
  mesh.polygons.reserve(faces.size());
  for (const auto& face : faces) {
    pcl::Vertices polygon;
    polygon.vertices = face;
    mesh.polygons.push_back(polygon);
  }
  return mesh;
}

pcl::PolygonMesh makeMesh(const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<Face>& faces) {
  for (const auto& face : faces) {
    if (face.size() < 3) {
      throw std::invalid_argument("makeMesh: a face needs at least 3 vertices");
    }
    for (const pcl::index_t index : face) {
      if (index < 0 || static_cast<std::size_t>(index) >= vertices.size()) {
        throw std::invalid_argument("makeMesh: vertex index " + std::to_string(index) +
                                    " out of range");
      }
    }
  }
  std::vector<Eigen::Vector3f> single;
  single.reserve(vertices.size());
  for (const auto& v : vertices)
    single.push_back(v.cast<float>());
  return meshOf(single, faces);
}

std::vector<Eigen::Vector3d> meshVertices(const pcl::PolygonMesh& mesh) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  pcl::fromPCLPointCloud2(mesh.cloud, cloud);
  std::vector<Eigen::Vector3d> vertices;
  vertices.reserve(cloud.size());
  for (const auto& p : cloud) {
    vertices.emplace_back(p.x, p.y, p.z);
  }
  return vertices;
}

std::vector<Triangle> triangulateFaces(const pcl::PolygonMesh& mesh) {
  std::vector<Triangle> triangles;
  for (const auto& polygon : mesh.polygons) {
    const auto& idx = polygon.vertices;
    for (std::size_t k = 1; k + 1 < idx.size(); ++k) {
      triangles.push_back({idx[0], idx[k], idx[k + 1]});
    }
  }
  return triangles;
}

double signedVolume(const pcl::PolygonMesh& mesh) {
  const auto vertices = meshVertices(mesh);
  double volume = 0.0;
  for (const auto& t : triangulateFaces(mesh)) {
    volume += vertices[t[0]].dot(vertices[t[1]].cross(vertices[t[2]]));
  }
  return volume / 6.0;
}

Eigen::Vector3d vectorArea(const pcl::PolygonMesh& mesh) {
  const auto vertices = meshVertices(mesh);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& t : triangulateFaces(mesh)) {
    sum += 0.5 * (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
  }
  return sum;
}

double surfaceArea(const pcl::PolygonMesh& mesh) {
  const auto vertices = meshVertices(mesh);
  double area = 0.0;
  for (const auto& t : triangulateFaces(mesh)) {
    area += 0.5 * (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]).norm();
  }
  return area;
}

Eigen::AlignedBox3d boundingBox(const pcl::PolygonMesh& mesh) {
  Eigen::AlignedBox3d box;  // default constructed: empty
  for (const auto& v : meshVertices(mesh)) {
    box.extend(v);
  }
  return box;
}

void appendMesh(pcl::PolygonMesh& a, const pcl::PolygonMesh& b) {
  auto vertices = meshVertices(a);
  const auto offset = static_cast<pcl::index_t>(vertices.size());
  const auto b_vertices = meshVertices(b);
  vertices.insert(vertices.end(), b_vertices.begin(), b_vertices.end());
  std::vector<Face> faces;
  for (const auto& polygon : a.polygons) {
    faces.emplace_back(polygon.vertices.begin(), polygon.vertices.end());
  }
  for (const auto& polygon : b.polygons) {
    Face face;
    for (const auto index : polygon.vertices) {
      face.push_back(index + offset);
    }
    faces.push_back(face);
  }
  a = makeMesh(vertices, faces);
}

pcl::PolygonMesh transformMesh(const pcl::PolygonMesh& mesh, const Eigen::Isometry3d& pose) {
  auto vertices = meshVertices(mesh);
  for (auto& v : vertices) {
    v = pose * v;
  }
  std::vector<Face> faces;
  for (const auto& polygon : mesh.polygons) {
    faces.emplace_back(polygon.vertices.begin(), polygon.vertices.end());
  }
  return makeMesh(vertices, faces);
}

}  // namespace synthetic
}  // namespace icf
}  // namespace pcl
