// Builds a one-triangle mesh and asks the installed library for a closest face.
#include <pcl/conversions.h>
#include <pcl/icf/closest_face_query.h>
#include <pcl/point_types.h>
#include <iostream>
int main() {
  pcl::PointCloud<pcl::PointXYZ> v;
  v.push_back({0, 0, 0}), v.push_back({1, 0, 0}), v.push_back({0, 1, 0});
  pcl::PolygonMesh mesh;
  pcl::toPCLPointCloud2(v, mesh.cloud);
  mesh.polygons.resize(1);
  mesh.polygons[0].vertices = {0, 1, 2};
  const auto faces = pcl::icf::FaceMesh::build(mesh);
  const auto hit = pcl::icf::makeClosestFaceIndex(faces)->closestFace({0.2f, 0.2f, 1.f});
  std::cout << "consumer: distance " << hit.distance << " to face " << hit.face << "\n";
  return hit.face == 0 && std::abs(hit.distance - 1.f) < 1e-6f ? 0 : 1;
}
