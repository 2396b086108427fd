// Whole-scene timing of the localizer: a synthetic 640x480 table-top scene with 3 objects
// (thesis scenario 1: Box5, a cup, a statue) and the real YCB-Video frame (4 touching
// objects), median of N runs, split into segmentation and registration.
//   build/release/bench/pcl_icf_localizer_bench [runs=9]
#include "synthetic/depth_camera.h"
#include "synthetic/synthetic_models.h"

#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/localization/object_localizer.h>
#include <pcl/io/pcd_io.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

using namespace pcl::icf;

namespace {

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

template <typename PointT>
void time(const std::string& name, const pcl::PointCloud<PointT>& scene, const IcfModel& model,
          int runs) {
  std::vector<double> seg, reg, total;
  std::size_t clusters = 0;
  bool found = false;
  for (int r = 0; r < runs; ++r) {
    const auto result = localization::localizeObject(scene, model);
    seg.push_back(result.segmentation_ms);
    reg.push_back(result.registration_ms);
    total.push_back(result.total_ms);
    clusters = result.clusters.size();
    found = result.status == localization::LocalizationStatus::Found;
  }
  std::printf("| %s | %zu | %zu | %s | %.1f | %.1f | %.1f |\n", name.c_str(), scene.size(),
              clusters, found ? "yes" : "no", median(seg), median(reg), median(total));
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 9;
  std::printf(
      "| scene | points | clusters tried | found | segmentation (ms) | registration (ms) "
      "| whole scene (ms) |\n|---|---|---|---|---|---|---|\n");
  const std::vector<synthetic::SyntheticModel> objects = {synthetic::thesisModel("Box5"),
                                                          synthetic::thesisModel("Cup"),
                                                          synthetic::thesisModel("Statue")};
  synthetic::ScanNoise noise;
  noise.outlier_ratio = 0.0;
  const auto scene =
      synthetic::makeTabletopScene(objects, {{0.0, 0.0, 0.4}, {-0.2, 0.05, 0.0}, {0.2, -0.03, 0.7}},
                                   synthetic::CameraIntrinsics(), noise);
  const auto box = IcfModel::build(objects.front().mesh);
  time("synthetic 640x480, 3 objects (Box5 target)", *scene.scan.cloud, *box, runs);

  const std::string dir = std::string(PCL_ICF_SHARED_DATA) + "/ycbv/";
  if (std::filesystem::exists(dir + "ycbv_frame000002.pcd")) {
    pcl::PointCloud<pcl::PointXYZRGB> ycb;
    pcl::io::loadPCDFile(dir + "ycbv_frame000002.pcd", ycb);
    for (const char* object : {"004_sugar_box_textured", "010_potted_meat_can_textured"}) {
      const auto model = IcfModel::build(io::loadPolygonMesh(dir + object + ".obj"));
      time(std::string("YCB-Video frame 2, ") + object, ycb, *model, std::max(1, runs / 3));
    }
  }
  return 0;
}
