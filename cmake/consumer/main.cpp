// Builds a one-triangle mesh and asks the installed library for a closest face, and the
// evaluation library for the MSSD of a known shift; pcl::IterativeClosestFace comes from its
// PCL-facing include.
#include <pcl/conversions.h>
#include <pcl/icf/evaluation/bop_pose_errors.h>
#include <pcl/icf/iterative_closest_face.h>
#include <pcl/icf/registration/closest_face_query.h>
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
  Eigen::Isometry3d shifted = Eigen::Isometry3d::Identity();
  shifted.translation() = Eigen::Vector3d(3, 4, 0);
  const double mssd =
      pcl::icf::evaluation::mssd(shifted, Eigen::Isometry3d::Identity(), {{0, 0, 0}, {1, 0, 0}},
                                 {Eigen::Isometry3d::Identity()});
  std::cout << "consumer: MSSD of a (3, 4, 0) shift " << mssd << "\n";
  const pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  std::cout << "consumer: " << icf.getClassName() << "\n";
  return hit.face == 0 && std::abs(hit.distance - 1.f) < 1e-6f && std::abs(mssd - 5.0) < 1e-12 ? 0
                                                                                               : 1;
}
