// The smallest real demo of the core, until pcl_icf_tool lands: load a scene cluster and a
// mesh, find the mesh's pose with pcl::IterativeClosestFace (no initial guess), print it, and
// compare with a ground-truth pose when one is given.
//   pcl_icf_demo CLUSTER.pcd MODEL.ply [TRUTH.txt]
// Exit codes: 0 pose found (and within 5 mm / 3 degrees of the truth when given), 1 nothing
// accepted or off the truth, 2 bad usage or bad input.
#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/registration/iterative_closest_face.h>
#include <pcl/io/pcd_io.h>

#include <Eigen/Geometry>

#include <cstdio>
#include <fstream>
#include <iostream>

namespace {

int usage(const char* program) {
  std::fprintf(stderr,
               "Usage: %s CLUSTER.pcd MODEL.{ply,obj,stl,vtk} [TRUTH.txt]\n"
               "  CLUSTER  points of one object, metres (NaN points are skipped)\n"
               "  MODEL    the object's mesh, metres\n"
               "  TRUTH    optional 4x4 model-to-scene pose (row-major, 16 numbers)\n",
               program);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3 || argc > 4)
    return usage(argv[0]);
  try {
    pcl::icf::io::requireReadableFile(argv[1]);
    auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    if (pcl::io::loadPCDFile(argv[1], *cloud) < 0 || cloud->empty())
      throw pcl::icf::io::FileError(std::string(argv[1]) + ": not a readable PCD cloud");
    const auto mesh = pcl::make_shared<pcl::PolygonMesh>(pcl::icf::io::loadPolygonMesh(argv[2]));

    pcl::IterativeClosestFace<pcl::PointXYZ> icf;
    icf.setInputTarget(mesh);
    icf.setInputSource(cloud);
    pcl::PointCloud<pcl::PointXYZ> aligned;
    icf.align(aligned);
    const pcl::icf::IcfResult& r = icf.getResult();
    const Eigen::Matrix4f pose = icf.getObjectPose();
    const Eigen::Quaternionf q(pose.topLeftCorner<3, 3>());
    std::printf("scene %s (%zu finite points), model %s (%zu faces)\n", argv[1], r.points, argv[2],
                icf.getModel()->mesh().size());
    std::printf("status %s via %s in %.1f ms; coverage %.2f, inliers %.2f, rmse %.2f mm\n",
                pcl::icf::toString(r.status).c_str(), r.method.c_str(), r.time_ms,
                r.quality.surface_coverage, r.quality.inlier_ratio, 1e3 * r.quality.rmse);
    std::cout << "model pose in the scene (model -> scene, metres):\n" << pose << "\n";
    std::printf("quaternion wxyz %.5f %.5f %.5f %.5f, translation %.4f %.4f %.4f m\n", q.w(), q.x(),
                q.y(), q.z(), pose(0, 3), pose(1, 3), pose(2, 3));
    if (argc == 4) {
      std::ifstream in(argv[3]);
      Eigen::Matrix4f truth;
      for (int i = 0; i < 16; ++i)
        if (!(in >> truth(i / 4, i % 4)))
          throw pcl::icf::io::FileError(std::string(argv[3]) + ": expected 16 numbers");
      const float dt = (pose.block<3, 1>(0, 3) - truth.block<3, 1>(0, 3)).norm();
      // The demo box is symmetric under 180-degree turns about its axes: take the smallest.
      float angle = 180.f;
      for (const Eigen::Matrix3f& S :
           {Eigen::Matrix3f(Eigen::Matrix3f::Identity()),
            Eigen::Matrix3f(Eigen::AngleAxisf(float(M_PI), Eigen::Vector3f::UnitX())),
            Eigen::Matrix3f(Eigen::AngleAxisf(float(M_PI), Eigen::Vector3f::UnitY())),
            Eigen::Matrix3f(Eigen::AngleAxisf(float(M_PI), Eigen::Vector3f::UnitZ()))})
        angle = std::min(angle, Eigen::AngleAxisf(truth.topLeftCorner<3, 3>().transpose() *
                                                  pose.topLeftCorner<3, 3>() * S)
                                        .angle() *
                                    180.f / float(M_PI));
      std::printf("against the ground truth: %.2f mm, %.2f degrees (box symmetry)\n", 1e3f * dt,
                  angle);
      return r.accepted() && dt <= 0.005f && angle <= 3.f ? 0 : 1;
    }
    return r.accepted() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcl_icf_demo: %s\n", e.what());
    return 2;
  }
}
