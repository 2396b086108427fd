// Table-top segmentation, stage by stage and whole, on two real 640x480 Kinect scenes from
// ../shared/data: the PCL milk scene (a floor with three bottles) and mOSD test55 (a table with
// 14 objects). Each stage gets the inputs the default pipeline would give it. Target: the whole
// segmentation in at most 150 ms on a 2-core machine.
//   build/release/bench/pcl_icf_segmentation_bench --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true   (one command line)
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <memory>
#include <numeric>
#include <string>

namespace {

namespace seg = pcl::icf::segmentation;
using Point = pcl::PointXYZRGBA;
using Cloud = pcl::PointCloud<Point>;

/** A scene and the intermediate results of the default pipeline, computed once. */
struct Scene {
  Cloud cloud;
  seg::TabletopParams params;
  pcl::Indices finite;
  Cloud reduced;
  pcl::Indices reduced_all;
  seg::TablePlane searched;  // on the voxel centroids
  seg::TablePlane plane;     // refitted on the full cloud
  Cloud hull;
  pcl::Indices above;
};

const Scene* scene(const std::string& relative) {
  static std::map<std::string, std::unique_ptr<Scene>> cache;
  auto it = cache.find(relative);
  if (it != cache.end())
    return it->second.get();
  std::unique_ptr<Scene> s;
  const std::string path = std::string(PCL_ICF_SHARED_DATA) + "/" + relative;
  if (std::filesystem::exists(path)) {
    s = std::make_unique<Scene>();
    if (pcl::io::loadPCDFile(path, s->cloud) != 0) {
      s.reset();
    } else {
      s->finite = seg::finiteIndices(s->cloud);
      s->reduced = seg::voxelDownsample(s->cloud, s->finite, s->params.voxel);
      s->reduced_all.resize(s->reduced.size());
      std::iota(s->reduced_all.begin(), s->reduced_all.end(), 0);
      s->searched = seg::findTablePlane(s->reduced, s->reduced_all, s->params.plane);
      s->plane = seg::refineTablePlane(s->cloud, s->finite, s->searched, s->params.plane);
      s->hull = seg::tableHull(s->reduced, s->searched.inliers, s->plane.coefficients);
      s->above =
          seg::aboveTableIndices(s->cloud, s->finite, s->hull, s->params.above_table).indices;
    }
  }
  return cache.emplace(relative, std::move(s)).first->second.get();
}

template <typename Body>
void run(benchmark::State& state, const std::string& relative, Body body) {
  const Scene* s = scene(relative);
  if (!s) {
    state.SkipWithError((relative + " missing from ../shared/data").c_str());
    return;
  }
  for (auto _ : state)
    body(*s);
}

void registerAll(const std::string& name, const std::string& relative) {
  const auto add = [&](const std::string& stage, auto body) {
    benchmark::RegisterBenchmark(
        (stage + "/" + name).c_str(),
        [relative, body](benchmark::State& state) { run(state, relative, body); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  };
  add("FiniteIndices",
      [](const Scene& s) { benchmark::DoNotOptimize(seg::finiteIndices(s.cloud)); });
  add("VoxelDownsample", [](const Scene& s) {
    benchmark::DoNotOptimize(seg::voxelDownsample(s.cloud, s.finite, s.params.voxel));
  });
  add("FindTablePlane", [](const Scene& s) {
    benchmark::DoNotOptimize(seg::findTablePlane(s.reduced, s.reduced_all, s.params.plane));
  });
  add("RefineTablePlane", [](const Scene& s) {
    benchmark::DoNotOptimize(seg::refineTablePlane(s.cloud, s.finite, s.searched, s.params.plane));
  });
  add("TableHull", [](const Scene& s) {
    benchmark::DoNotOptimize(seg::tableHull(s.reduced, s.searched.inliers, s.plane.coefficients));
  });
  add("AboveTableIndices", [](const Scene& s) {
    benchmark::DoNotOptimize(
        seg::aboveTableIndices(s.cloud, s.finite, s.hull, s.params.above_table));
  });
  for (const auto method : {seg::ClusterMethod::Grid, seg::ClusterMethod::PclOrganized,
                            seg::ClusterMethod::PclKdTree}) {
    add(std::string("ExtractClusters_") + seg::toString(method), [method](const Scene& s) {
      seg::ClusterParams p = s.params.cluster;
      p.method = method;
      benchmark::DoNotOptimize(seg::extractClusters(s.cloud, s.above, p));
    });
  }
  add("SegmentTabletop",
      [](const Scene& s) { benchmark::DoNotOptimize(seg::segmentTabletop(s.cloud, s.params)); });
  add("SegmentTabletop_NoVoxel", [](const Scene& s) {
    seg::TabletopParams p = s.params;
    p.voxel.voxel_size = 0.0;
    benchmark::DoNotOptimize(seg::segmentTabletop(s.cloud, p));
  });
}

const bool registered = [] {
  registerAll("milk", "pcl/milk_cartoon_all_small_clorox.pcd");
  registerAll("mosd_test55", "mosd/test55.pcd");
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
