// Writes the bundled demo (data/demo/README.md): a simulated Kinect view (1.5 mm noise at 1 m,
// 5% outliers) of the thesis's Box5 at a fixed pose, the mesh, and the ground-truth pose; and a
// 320 x 240 organized table-top scene with Box5 and two distractors (a cup and a statue) with
// Box5's ground-truth pose, the default scene of pcl_icf_tool. Deterministic.
//   make_demo_scene OUTPUT_DIR
#include "synthetic/depth_camera.h"
#include "synthetic/synthetic_models.h"

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <cmath>
#include <cstdio>
#include <fstream>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "Usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  const auto model = pcl::icf::synthetic::thesisModel("Box5");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.05, -0.03, 0.85);
  pose.rotate(Eigen::AngleAxisd(0.9, Eigen::Vector3d(0.4, 1.0, 0.3).normalized()));
  pcl::icf::synthetic::ScanNoise noise;
  noise.seed = 2013;
  const auto cluster = pcl::icf::synthetic::renderCluster(
      model.mesh, pose, pcl::icf::synthetic::CameraIntrinsics(), noise);
  pcl::io::savePCDFileBinaryCompressed(dir + "/box5_cluster.pcd", *cluster);
  pcl::io::savePLYFile(dir + "/box5.ply", model.mesh);
  std::ofstream truth(dir + "/box5_truth.txt");
  truth.precision(9);
  truth << pose.matrix() << "\n";
  std::printf("wrote %zu points, the mesh and the pose to %s\n", cluster->size(), dir.c_str());

  // The table-top scene: a Kinect's field of view at half resolution, camera 0.6 m above the
  // table looking down at 45 degrees (makeTabletopScene), Box5 in front, two distractors.
  pcl::icf::synthetic::CameraIntrinsics half;
  half.width = 320;
  half.height = 240;
  half.fx = half.fy = 262.5;
  half.cx = 159.5;
  half.cy = 119.5;
  pcl::icf::synthetic::ScanNoise table_noise;
  table_noise.seed = 2014;
  const std::vector<pcl::icf::synthetic::SyntheticModel> objects = {
      model, pcl::icf::synthetic::thesisModel("Cup"), pcl::icf::synthetic::thesisModel("Statue")};
  const std::vector<Eigen::Vector3d> placement = {
      {0.02, -0.05, 0.5}, {-0.22, 0.08, 0.0}, {0.22, 0.10, -0.4}};
  const auto scene = pcl::icf::synthetic::makeTabletopScene(objects, placement, half, table_noise);
  pcl::io::savePCDFileBinaryCompressed(dir + "/tabletop_box5.pcd", *scene.scan.cloud);
  std::ofstream table_truth(dir + "/tabletop_box5_truth.txt");
  table_truth.precision(9);
  table_truth << scene.poses[0].matrix() << "\n";
  std::size_t finite = 0;
  for (const auto& p : *scene.scan.cloud)
    finite += std::isfinite(p.z);
  std::printf("wrote a %ux%u table-top scene (%zu finite points) and Box5's pose to %s\n",
              scene.scan.cloud->width, scene.scan.cloud->height, finite, dir.c_str());
  return 0;
}
