// Writes the bundled demo: a simulated Kinect view (1.5 mm noise at 1 m, 5% outliers) of the
// thesis's Box5 at a fixed pose, the mesh, and the ground-truth pose. Deterministic.
//   make_demo_scene OUTPUT_DIR
#include "support/depth_camera.h"
#include "support/synthetic_models.h"

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <cstdio>
#include <fstream>

int
main(int argc, char** argv)
{
  if (argc != 2) {
    std::fprintf(stderr, "Usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  const auto model = pcl::icf::test::thesisModel("Box5");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.05, -0.03, 0.85);
  pose.rotate(Eigen::AngleAxisd(0.9, Eigen::Vector3d(0.4, 1.0, 0.3).normalized()));
  pcl::icf::test::ScanNoise noise;
  noise.seed = 2013;
  const auto cluster =
      pcl::icf::test::renderCluster(model.mesh, pose, pcl::icf::test::CameraIntrinsics(), noise);
  pcl::io::savePCDFileBinaryCompressed(dir + "/box5_cluster.pcd", *cluster);
  pcl::io::savePLYFile(dir + "/box5.ply", model.mesh);
  std::ofstream truth(dir + "/box5_truth.txt");
  truth.precision(9);
  truth << pose.matrix() << "\n";
  std::printf("wrote %zu points, the mesh and the pose to %s\n", cluster->size(), dir.c_str());
  return 0;
}
