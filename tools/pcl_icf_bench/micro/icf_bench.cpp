// Per model: success rate (<= 5 mm and 3 degrees, symmetry-aware), median translation and
// rotation error and median time per cluster, for ICF's fast and thesis strategies and for
// pcl::IterativeClosestPoint on mesh samples from the centroid start, on synthetic depth
// views of the thesis's four models at random poses (seeded).
//   build/release/bench/pcl_icf_icf_bench [trials=50] [thesis_trials=3] > table.md
#include "synthetic/depth_camera.h"
#include "synthetic/pose_error.h"
#include "synthetic/synthetic_models.h"

#include <pcl/icf/registration/iterative_closest_face.h>
#include <pcl/registration/icp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

namespace {

using namespace pcl::icf;
using Clock = std::chrono::steady_clock;

struct Stats {
  std::vector<double> t_mm, r_deg, ms, points;
  int ok = 0;
};

double median(std::vector<double> v) {
  if (v.empty())
    return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

using Method = std::function<Eigen::Matrix4f(const pcl::PointCloud<pcl::PointXYZ>::Ptr&)>;

Stats run(const synthetic::SyntheticModel& model, const Method& method, int trials) {
  Stats s;
  for (int trial = 0; trial < trials; ++trial) {
    const auto [truth, cluster] =
        synthetic::randomView(model.mesh, 5000 + static_cast<std::uint64_t>(trial));
    s.points.push_back(static_cast<double>(cluster->size()));
    const auto start = Clock::now();
    const Eigen::Matrix4f pose = method(cluster);
    s.ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    const auto e =
        synthetic::poseError(Eigen::Isometry3d(pose.cast<double>()), truth, model.symmetry);
    s.t_mm.push_back(1e3 * e.translation);
    s.r_deg.push_back(e.rotation_deg);
    s.ok += e.translation <= 0.005 && e.rotation_deg <= 3.0;
  }
  return s;
}

void row(const std::string& model, const std::string& method, const Stats& s) {
  std::printf("| %s | %s | %zu | %.0f | %.0f%% | %.2f | %.2f | %.1f |\n", model.c_str(),
              method.c_str(), s.ms.size(), median(s.points),
              100.0 * s.ok / std::max<std::size_t>(1, s.ms.size()), median(s.t_mm), median(s.r_deg),
              median(s.ms));
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const int trials = argc > 1 ? std::max(1, std::atoi(argv[1])) : 50;
  const int thesis_trials = argc > 2 ? std::max(0, std::atoi(argv[2])) : 3;
  std::printf(
      "| model | method | trials | median points | success (5 mm, 3 deg) | median t err (mm) | "
      "median r err (deg) | median time (ms) |\n|---|---|---|---|---|---|---|---|\n");
  for (const std::string& name : synthetic::thesisModelNames()) {
    const synthetic::SyntheticModel model = synthetic::thesisModel(name);
    const auto mesh = pcl::make_shared<pcl::PolygonMesh>(model.mesh);
    const IcfModel::ConstPtr prepared = IcfModel::build(model.mesh);

    pcl::IterativeClosestFace<pcl::PointXYZ> icf;
    icf.setInputModel(prepared);
    auto viaIcf = [&icf](const pcl::PointCloud<pcl::PointXYZ>::Ptr& cluster) {
      icf.setInputSource(cluster);
      pcl::PointCloud<pcl::PointXYZ> aligned;
      icf.align(aligned);
      return icf.getObjectPose();
    };
    icf.setSearchStrategy(SearchStrategy::Fast);
    row(name, "ICF fast (default)", run(model, viaIcf, trials));
    if (thesis_trials > 0) {
      icf.setSearchStrategy(SearchStrategy::Thesis);
      row(name, "ICF thesis (50x100x20)", run(model, viaIcf, thesis_trials));
    }

    auto samples = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    for (const auto& s : prepared->samples())
      samples->push_back(pcl::PointXYZ(s.point.x(), s.point.y(), s.point.z()));
    auto viaIcp = [&](const pcl::PointCloud<pcl::PointXYZ>::Ptr& cluster) {
      pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
      icp.setInputSource(cluster);
      icp.setInputTarget(samples);
      icp.setMaximumIterations(50);
      icp.setMaxCorrespondenceDistance(0.05);
      Eigen::Vector4f c;
      pcl::compute3DCentroid(*cluster, c);
      Eigen::Matrix4f guess = Eigen::Matrix4f::Identity();  // centroid start, no rotation
      guess.block<3, 1>(0, 3) = prepared->mesh().surfaceCentroid() - c.head<3>();
      pcl::PointCloud<pcl::PointXYZ> aligned;
      icp.align(aligned, guess);
      return Eigen::Matrix4f(icp.getFinalTransformation().inverse());
    };
    row(name, "PCL ICP, centroid start", run(model, viaIcp, trials));
  }
  return 0;
}
