/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_bench --bop (bench_bop.h): the dataset read by pcl/icf/io/bop_dataset.h, the poses by
// localizeObjects, the errors and recalls by pcl/icf/evaluation/. The results CSV is BOP's
// (bop_toolkit's docs: scene_id,im_id,obj_id,score,R,t,time; R row-major and t in mm,
// space-separated; time per image in seconds, the same on every row of an image).
#include "bench_bop.h"

#include "common/arguments.h"

#include <pcl/icf/evaluation/bop_pose_errors.h>
#include <pcl/icf/evaluation/bop_recall.h>
#include <pcl/icf/io/bop_dataset.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/localization/objects_localizer.h>
#include <pcl/icf/model_file.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace pcl_icf_bench {

namespace {

namespace fs = std::filesystem;
namespace eval = pcl::icf::evaluation;
namespace bop = pcl::icf::io;
using pcl_icf_tools::ArgumentReader;
using pcl_icf_tools::UsageError;

struct BopOptions {
  fs::path root;
  std::string split = "test";
  fs::path targets;  ///< default ROOT/test_targets_bop19.json
  fs::path out_dir = "out/bop";
  int threads = 0;
  unsigned seed = 1;
  /** Instances seen less than this are not counted (BOP 2019's targets are those seen 10%). */
  double visib_gt_min = 0.1;
  double vsd_delta_mm = 15.0;  ///< BOP 2019's delta for every dataset but ITODD (5)
};

BopOptions parseBopOptions(int argc, char** argv) {
  BopOptions o;
  ArgumentReader args(argc, argv);
  while (!args.done()) {
    const std::string a = args.next();
    if (a == "--bop")
      o.root = args.value(a);
    else if (a == "--split")
      o.split = args.value(a);
    else if (a == "--targets")
      o.targets = args.value(a);
    else if (a == "--out")
      o.out_dir = args.value(a);
    else if (a == "--threads")
      o.threads = static_cast<int>(pcl_icf_tools::parseInteger(a, args.value(a), 0, 256));
    else if (a == "--seed")
      o.seed = static_cast<unsigned>(pcl_icf_tools::parseSeed(a, args.value(a)));
    else if (a == "--vsd-delta")
      o.vsd_delta_mm = pcl_icf_tools::parsePositive(a, args.value(a));
    else
      throw UsageError("--bop: unknown option " + a);
  }
  if (o.root.empty())
    throw UsageError("--bop ROOT: the dataset's folder");
  if (o.targets.empty())
    o.targets = o.root / "test_targets_bop19.json";
  return o;
}

/** A dataset's object: its mesh (mm), its model (m), its vertices and symmetries (mm). */
struct BopObject {
  pcl::icf::IcfModel::ConstPtr model;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Isometry3d> symmetries;
  double diameter_mm = 0.0;
};

BopObject loadObject(const fs::path& root, int obj_id, const bop::BopModelInfo& info) {
  char name[32];
  std::snprintf(name, sizeof name, "obj_%06d.ply", obj_id);
  const fs::path path = root / "models" / name;
  BopObject o;
  const pcl::PolygonMesh mesh = bop::loadPolygonMesh(path.string());
  pcl::icf::IcfModelParams params;
  params.mesh.scale = 1e-3f;  // BOP's models are in millimetres
  o.model = pcl::icf::buildModelCached(mesh, params, pcl::icf::defaultModelCacheFolder()).model;
  // The errors' points: the mesh's vertices as the model read them (any vertex type), in mm.
  for (const Eigen::Vector3f& v : o.model->mesh().vertices())
    o.vertices.push_back(v.cast<double>() * 1000.0);
  std::vector<eval::ContinuousSymmetry> continuous;
  for (const auto& c : info.symmetries_continuous)
    continuous.push_back({c.axis, c.offset});
  o.symmetries = eval::symmetryTransformations(info.symmetries_discrete, continuous, 0.01);
  o.diameter_mm = info.diameter;
  return o;
}

/** One row of the results CSV. */
struct Estimate {
  int scene_id = 0, im_id = 0, obj_id = 0;
  double score = 0.0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< model -> camera, mm
  double seconds = 0.0;
};

std::string sceneFolder(const BopOptions& o, int scene_id) {
  char name[16];
  std::snprintf(name, sizeof name, "%06d", scene_id);
  return (o.root / o.split / name).string();
}

std::string imageFile(const std::string& scene, const char* kind, int im_id) {
  char name[32];
  std::snprintf(name, sizeof name, "%06d.png", im_id);
  return (fs::path(scene) / kind / name).string();
}

/** The camera-frame depth in metres of an organized cloud, 0 where NaN. */
eval::DepthMap depthOf(const pcl::PointCloud<pcl::PointXYZRGBA>& cloud) {
  eval::DepthMap d{static_cast<int>(cloud.width), static_cast<int>(cloud.height), {}};
  d.z.reserve(cloud.size());
  for (const auto& p : cloud)
    d.z.push_back(std::isfinite(p.z) ? p.z : 0.f);
  return d;
}

/** What the scores need of one image: its ground truth, visibility, camera and depth. */
struct ImageTruth {
  std::vector<bop::BopPose> gt;
  std::vector<double> visib;
  bop::BopCamera camera;
  eval::DepthMap depth;  ///< metres
};

void writeCsv(const fs::path& path, const std::vector<Estimate>& rows) {
  std::ofstream out(path);
  out << "scene_id,im_id,obj_id,score,R,t,time\n";
  char buf[512];
  for (const Estimate& e : rows) {
    const Eigen::Matrix3d R = e.pose.linear();
    const Eigen::Vector3d t = e.pose.translation();
    std::snprintf(
        buf, sizeof buf,
        "%d,%d,%d,%.6f,%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f,%.6f %.6f %.6f,%.3f\n",
        e.scene_id, e.im_id, e.obj_id, e.score, R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1),
        R(1, 2), R(2, 0), R(2, 1), R(2, 2), t.x(), t.y(), t.z(), e.seconds);
    out << buf;
  }
  if (!out)
    throw std::runtime_error(path.string() + ": cannot be written");
}

/** The three recalls of one set of targets. */
struct Scores {
  std::size_t instances = 0;
  double vsd = 0.0, mssd = 0.0, mspd = 0.0;
  double ar() const { return (vsd + mssd + mspd) / 3.0; }
};

}  // namespace

int runBop(int argc, char** argv) {
  BopOptions o;
  try {
    o = parseBopOptions(argc, argv);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "pcl_icf_bench: %s\n", e.what());
    return 2;
  }
  try {
    const bop::BopCamera dataset_camera =
        bop::readBopDatasetCamera((o.root / "camera.json").string());
    const auto infos = bop::readBopModelsInfo((o.root / "models" / "models_info.json").string());
    const std::vector<bop::BopTarget> targets = bop::readBopTargets(o.targets.string());
    // Targets by image, in (scene, image) order.
    std::map<std::pair<int, int>, std::vector<bop::BopTarget>> by_image;
    for (const auto& t : targets) {
      if (!infos.count(t.obj_id))
        throw bop::FileError(o.targets.string() + ": object " + std::to_string(t.obj_id) +
                             " has no entry in models_info.json");
      by_image[{t.scene_id, t.im_id}].push_back(t);
    }
    std::map<int, BopObject> objects;
    for (const auto& t : targets)
      if (!objects.count(t.obj_id))
        objects[t.obj_id] = loadObject(o.root, t.obj_id, infos.at(t.obj_id));

    pcl::icf::localization::LocalizerParams params;
    params.threads = o.threads;
    params.icf.seed = o.seed;
    std::vector<Estimate> rows;
    std::map<std::pair<int, int>, ImageTruth> truth;
    std::map<int, std::map<int, bop::BopCamera>> cameras;
    std::map<int, std::map<int, std::vector<bop::BopPose>>> gts;
    std::map<int, std::map<int, std::vector<double>>> visibs;
    std::size_t done = 0;
    for (const auto& [image, image_targets] : by_image) {
      const auto [scene_id, im_id] = image;
      const std::string scene = sceneFolder(o, scene_id);
      if (!cameras.count(scene_id)) {
        cameras[scene_id] = bop::readBopSceneCamera(scene + "/scene_camera.json",
                                                    dataset_camera.width, dataset_camera.height);
        gts[scene_id] = bop::readBopSceneGt(scene + "/scene_gt.json");
        visibs[scene_id] = bop::readBopSceneVisibility(scene + "/scene_gt_info.json");
      }
      if (!cameras[scene_id].count(im_id))
        throw bop::FileError(scene + "/scene_camera.json: image " + std::to_string(im_id) +
                             " is missing");
      if (!gts[scene_id].count(im_id) || !visibs[scene_id].count(im_id))
        throw bop::FileError(scene + ": image " + std::to_string(im_id) +
                             " is missing from scene_gt.json or scene_gt_info.json");
      ImageTruth& it = truth[image];
      it.camera = cameras[scene_id].at(im_id);
      it.gt = gts[scene_id].at(im_id);
      it.visib = visibs[scene_id].at(im_id);
      if (it.gt.size() != it.visib.size())
        throw bop::FileError(scene + ": image " + std::to_string(im_id) + " has " +
                             std::to_string(it.gt.size()) + " instances in scene_gt.json and " +
                             std::to_string(it.visib.size()) + " in scene_gt_info.json");
      const std::string rgb = imageFile(scene, "rgb", im_id);
      const auto cloud = bop::readBopDepthImage(imageFile(scene, "depth", im_id), it.camera,
                                                fs::exists(rgb) ? rgb : "");
      it.depth = depthOf(*cloud);
      std::vector<pcl::icf::localization::ObjectQuery> queries;
      for (const auto& t : image_targets)
        queries.push_back(
            {objects.at(t.obj_id).model, "obj_" + std::to_string(t.obj_id), t.inst_count});
      const auto start = std::chrono::steady_clock::now();
      const auto found = pcl::icf::localization::localizeObjects(*cloud, queries, params);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      for (std::size_t k = 0; k < image_targets.size(); ++k)
        for (const int h : found.objects[k].instances) {
          const auto& c = found.objects[k].clusters[static_cast<std::size_t>(h)];
          Estimate e;
          e.scene_id = scene_id;
          e.im_id = im_id;
          e.obj_id = image_targets[k].obj_id;
          e.score = c.verification.confidence;
          e.pose.matrix() = c.icf.object_pose.cast<double>();
          e.pose.translation() *= 1000.0;  // metres -> BOP's millimetres
          e.seconds = seconds;
          rows.push_back(e);
        }
      std::fprintf(stderr, "\r%zu/%zu images", ++done, by_image.size());
    }
    std::fputs("\n", stderr);
    fs::create_directories(o.out_dir);
    // BOP's name: METHOD_DATASET-SPLIT.csv, the dataset's folder name (ROOT/ or ROOT alike).
    const fs::path root = o.root.lexically_normal();
    const std::string dataset =
        (root.filename().empty() ? root.parent_path().filename() : root.filename()).string();
    const fs::path csv = o.out_dir / ("pcl-icf_" + dataset + "-" + o.split + ".csv");
    writeCsv(csv, rows);

    // Errors of every estimate against every instance of its object in its image.
    const std::vector<double> fractions = eval::bopFractions();
    const std::vector<double> mspd_th = eval::bopMspdThresholds(dataset_camera.width);
    std::map<int, std::vector<eval::MatchGroup>> vsd_groups[10], mssd_groups, mspd_groups;
    for (const auto& [image, image_targets] : by_image) {
      const ImageTruth& it = truth.at(image);
      for (const auto& t : image_targets) {
        const BopObject& obj = objects.at(t.obj_id);
        std::vector<std::size_t> instances;
        for (std::size_t g = 0; g < it.gt.size(); ++g)
          if (it.gt[g].obj_id == t.obj_id)
            instances.push_back(g);
        eval::MatchGroup base;
        base.max_estimates = static_cast<std::size_t>(t.inst_count);
        for (const std::size_t g : instances)
          base.gt_valid.push_back(g < it.visib.size() && it.visib[g] >= o.visib_gt_min);
        eval::MatchGroup vsd[10], mssd = base, mspd = base;
        for (auto& v : vsd)
          v = base;
        for (const Estimate& e : rows) {
          if (e.scene_id != image.first || e.im_id != image.second || e.obj_id != t.obj_id)
            continue;
          eval::MatchGroup::Estimate ev[10], es{e.score, {}}, ep{e.score, {}};
          for (auto& v : ev)
            v.score = e.score;
          for (const std::size_t g : instances) {
            const Eigen::Isometry3d& gt = it.gt[g].model_to_camera;
            es.errors.push_back(eval::mssd(e.pose, gt, obj.vertices, obj.symmetries) /
                                obj.diameter_mm);
            ep.errors.push_back(eval::mspd(e.pose, gt, it.camera.K, obj.vertices, obj.symmetries));
            Eigen::Isometry3d est_m = e.pose, gt_m = gt;
            est_m.translation() /= 1000.0;
            gt_m.translation() /= 1000.0;
            const auto v = eval::vsd(*obj.model, est_m, gt_m, it.depth, it.camera.K,
                                     o.vsd_delta_mm / 1000.0, fractions, obj.diameter_mm / 1000.0);
            for (std::size_t k = 0; k < 10; ++k)
              ev[k].errors.push_back(v[k]);
          }
          mssd.estimates.push_back(es);
          mspd.estimates.push_back(ep);
          for (std::size_t k = 0; k < 10; ++k)
            vsd[k].estimates.push_back(ev[k]);
        }
        mssd_groups[t.obj_id].push_back(mssd);
        mspd_groups[t.obj_id].push_back(mspd);
        for (std::size_t k = 0; k < 10; ++k)
          vsd_groups[k][t.obj_id].push_back(vsd[k]);
      }
    }
    const auto scoresOf = [&](const std::set<int>& ids) {
      Scores s;
      std::vector<eval::MatchGroup> ms, mp, mv[10];
      for (const int id : ids) {
        ms.insert(ms.end(), mssd_groups[id].begin(), mssd_groups[id].end());
        mp.insert(mp.end(), mspd_groups[id].begin(), mspd_groups[id].end());
        for (std::size_t k = 0; k < 10; ++k)
          mv[k].insert(mv[k].end(), vsd_groups[k][id].begin(), vsd_groups[k][id].end());
      }
      for (const auto& g : ms)
        s.instances +=
            static_cast<std::size_t>(std::count(g.gt_valid.begin(), g.gt_valid.end(), true));
      s.mssd = eval::averageRecall(ms, fractions);
      s.mspd = eval::averageRecall(mp, mspd_th);
      for (std::size_t k = 0; k < 10; ++k)
        s.vsd += eval::averageRecall(mv[k], fractions) / 10.0;
      return s;
    };
    std::ostringstream md;
    md << "BOP scores of " << o.root.string() << " (" << o.split << ", " << by_image.size()
       << " images, " << rows.size() << " estimates; " << csv.string() << ")\n\n"
       << "| object | instances | AR_VSD | AR_MSSD | AR_MSPD | AR "
          "|\n|---|---:|---:|---:|---:|---:|\n";
    char line[160];
    std::set<int> all;
    for (const auto& [id, obj] : objects) {
      all.insert(id);
      const Scores s = scoresOf({id});
      std::snprintf(line, sizeof line, "| %d | %zu | %.3f | %.3f | %.3f | %.3f |\n", id,
                    s.instances, s.vsd, s.mssd, s.mspd, s.ar());
      md << line;
    }
    const Scores s = scoresOf(all);
    std::snprintf(line, sizeof line, "| all | %zu | %.3f | %.3f | %.3f | **%.3f** |\n", s.instances,
                  s.vsd, s.mssd, s.mspd, s.ar());
    md << line;
    std::ofstream(o.out_dir / "bop_scores.md") << md.str();
    std::fputs(md.str().c_str(), stdout);
    return 0;
  } catch (const bop::FileError& e) {
    std::fprintf(stderr, "pcl_icf_bench: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcl_icf_bench: %s\n", e.what());
    return 2;
  }
}

}  // namespace pcl_icf_bench
