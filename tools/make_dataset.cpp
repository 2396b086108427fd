// pcl_icf_make_dataset: writes a seeded synthetic benchmark suite for pcl_icf_bench — the
// thesis's models (chapter 6-7) seen by a simulated Kinect — and its manifest
// (doc/DATASETS.md).
//
//   pcl_icf_make_dataset --out DIR [--manifest FILE] [--kind views|tabletop] [--cases N]
//                        [--models Box5,YellowRoundSalt,EisKaffe,Amicelly] [--seed S]
//
// --kind views (default): per model N single-object clusters, the model at a uniformly random
//   rotation, x, y in [-0.15, 0.15] m and 0.7-1.1 m in front of the camera (the test support's
//   randomTabletopPose), rendered alone (renderCluster); groups are the model names.
// --kind tabletop: the thesis's scenarios 1, 2, 3 and 5 (section 6.2) rebuilt: the target and
//   its neighbours stand upright at random non-overlapping places on a table seen from
//   0.5-0.8 m above at 35-60 degrees (makeTabletopScene); the cluster is the target's own
//   pixels (an oracle segmentation, occlusion by the neighbours included). Groups S1-Box5
//   (with a cup and the statue), S2-Box5 (with a larger box), S3-YellowRoundSalt (with Box5),
//   S5-Amicelly and S5-EisKaffe (the two together). --models filters by target model.
// Noise everywhere: 1.5 mm at 1 m growing with depth^2, 5% outliers within +-5 cm along the
// ray (test::ScanNoise defaults). Case k of a group draws from std::mt19937_64 seeded with
// seed + 1000 * group + k, so adding cases never changes the earlier ones.
//
// Writes DIR/models/<Model>.ply (binary PLY, metres), DIR/<kind>/<case>.pcd (binary_compressed PCD,
// PointXYZ, camera at the origin) and the manifest (default DIR/manifest.txt) whose paths are
// relative to the manifest's directory. Exit codes: 0 written, 2 bad usage or I/O error.
#include "comma_list.h"
#include "support/depth_camera.h"
#include "support/mesh_geometry.h"
#include "support/pose_error.h"
#include "support/synthetic_models.h"

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
namespace t = pcl::icf::test;

struct Options {
  fs::path out;
  fs::path manifest;
  std::string kind = "views";
  int cases = 30;
  std::vector<std::string> models = {"Box5", "YellowRoundSalt", "EisKaffe", "Amicelly"};
  std::uint64_t seed = 2013;
};

int usage(const char* program) {
  std::fprintf(stderr,
               "Usage: %s --out DIR [--manifest FILE] [--kind views|tabletop] [--cases N]\n"
               "          [--models A,B,...] [--seed S]\n"
               "Writes a seeded synthetic suite of the thesis's models and its manifest\n"
               "(format: doc/DATASETS.md). Defaults: views, 30 cases per group, the four\n"
               "thesis models, seed 2013, manifest DIR/manifest.txt.\n",
               program);
  return 2;
}

/** The manifest's symmetry spec of a model (doc/DATASETS.md), from its name. */
std::string symmetrySpec(const std::string& name) {
  static const std::map<std::string, std::string> specs = {
      {"Box5", "box:0.14,0.09,0.05"}, {"YellowRoundSalt", "cylinder"}, {"EisKaffe", "cylinder"},
      {"Amicelly", "prism:6"},        {"Cup", "cylinder:noflip"},      {"Statue", "none"}};
  const auto it = specs.find(name);
  if (it == specs.end())
    throw std::invalid_argument("no symmetry spec for model " + name);
  return it->second;
}

std::string truthSpec(const Eigen::Isometry3d& pose) {
  std::ostringstream out;
  out.precision(9);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      out << (r || c ? "," : "") << pose.matrix()(r, c);
  return out.str();
}

struct Case {
  std::string name, group, model;
  Eigen::Isometry3d truth;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cluster;
};

/** One view of the model alone at a random pose; redrawn while fewer than 200 points show. */
Case makeView(const t::SyntheticModel& model, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Case c;
  c.model = model.name;
  do {
    c.truth = t::randomTabletopPose(rng);
    t::ScanNoise noise;
    noise.seed = rng();
    c.cluster = t::renderCluster(model.mesh, c.truth, t::CameraIntrinsics(), noise);
  } while (c.cluster->size() < 200);
  return c;
}

/** A thesis scenario: the target (objects[0]) and its neighbours upright on the table at
 * random places at least 2 cm apart (bounding circles); redrawn while the target shows fewer
 * than 200 points. */
Case makeTabletop(const std::vector<t::SyntheticModel>& objects, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> x(-0.25, 0.25), y(-0.15, 0.15), yaw(-M_PI, M_PI);
  std::uniform_real_distribution<double> height(0.5, 0.8), tilt(35.0, 60.0);
  std::vector<double> radius;
  for (const auto& o : objects) {
    const Eigen::AlignedBox3d box = t::boundingBox(o.mesh);
    radius.push_back(0.5 * (box.max() - box.min()).head<2>().norm());
  }
  for (;;) {
    std::vector<Eigen::Vector3d> placement;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      Eigen::Vector3d p;
      bool free = false;
      for (int attempt = 0; attempt < 1000 && !free; ++attempt) {
        p = Eigen::Vector3d(x(rng), y(rng), yaw(rng));
        free = true;
        for (std::size_t j = 0; j < placement.size(); ++j)
          free =
              free && (p.head<2>() - placement[j].head<2>()).norm() > radius[i] + radius[j] + 0.02;
      }
      placement.push_back(p);
    }
    t::ScanNoise noise;
    noise.seed = rng();
    const double h = height(rng), a = tilt(rng);
    const t::TabletopScene scene =
        t::makeTabletopScene(objects, placement, t::CameraIntrinsics(), noise, h, a);
    Case c;
    c.model = objects[0].name;
    c.truth = scene.poses[0];
    c.cluster = t::extractLabelCloud(scene.scan, 1);
    if (c.cluster->size() >= 200)
      return c;
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc)
          throw std::invalid_argument(arg + " needs a value");
        return argv[++i];
      };
      if (arg == "--out")
        opt.out = value();
      else if (arg == "--manifest")
        opt.manifest = value();
      else if (arg == "--kind")
        opt.kind = value();
      else if (arg == "--cases")
        opt.cases = std::stoi(value());
      else if (arg == "--models")
        opt.models = pcl_icf_tools::splitComma(value());
      else if (arg == "--seed")
        opt.seed = std::stoull(value());
      else if (arg == "-h" || arg == "--help")
        return usage(argv[0]) - 2;
      else
        throw std::invalid_argument("unknown option " + arg);
    }
    if (opt.out.empty())
      throw std::invalid_argument("--out is required");
    if (opt.kind != "views" && opt.kind != "tabletop")
      throw std::invalid_argument("--kind must be views or tabletop, not " + opt.kind);
    if (opt.cases < 1 || opt.cases > 100000)
      throw std::invalid_argument("--cases must lie in [1, 100000]");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcl_icf_make_dataset: %s\n", e.what());
    return usage(argv[0]);
  }
  if (opt.manifest.empty())
    opt.manifest = opt.out / "manifest.txt";

  try {
    // Groups: (name, target + neighbours).
    std::vector<std::pair<std::string, std::vector<std::string>>> groups;
    if (opt.kind == "views") {
      for (const auto& m : opt.models)
        groups.push_back({m, {m}});
    } else {
      const std::vector<std::pair<std::string, std::vector<std::string>>> scenarios = {
          {"S1-Box5", {"Box5", "Cup", "Statue"}},
          {"S2-Box5", {"Box5", "LargeBox"}},
          {"S3-YellowRoundSalt", {"YellowRoundSalt", "Box5"}},
          {"S5-Amicelly", {"Amicelly", "EisKaffe"}},
          {"S5-EisKaffe", {"EisKaffe", "Amicelly"}}};
      for (const auto& s : scenarios)
        if (std::find(opt.models.begin(), opt.models.end(), s.second[0]) != opt.models.end())
          groups.push_back(s);
    }
    auto modelByName = [](const std::string& name) {
      if (name == "LargeBox") {  // scenario 2's "another rectangular shaped object"
        t::SyntheticModel m;
        m.name = name;
        m.mesh = t::makeBox(0.20, 0.12, 0.08);
        m.symmetry = t::Symmetry::box(0.20, 0.12, 0.08);
        return m;
      }
      return t::thesisModel(name);
    };

    const fs::path base =
        opt.manifest.parent_path().empty() ? fs::path(".") : opt.manifest.parent_path();
    fs::create_directories(opt.out / "models");
    fs::create_directories(opt.out / opt.kind);
    fs::create_directories(base);
    std::ofstream manifest(opt.manifest);
    if (!manifest)
      throw std::runtime_error("cannot write " + opt.manifest.string());
    manifest << "# pcl_icf bench manifest v1 (doc/DATASETS.md)\n"
             << "# written by: pcl_icf_make_dataset --kind " << opt.kind << " --cases " << opt.cases
             << " --seed " << opt.seed << "\n"
             << "# Simulated Kinect (640x480, f 525 px), noise 1.5 mm at 1 m ~ depth^2, 5% "
                "outliers within +-5 cm; scenes in metres, camera at the origin.\n";
    const bool tty = isatty(STDERR_FILENO);
    std::size_t written = 0;
    for (std::size_t g = 0; g < groups.size(); ++g) {
      std::vector<t::SyntheticModel> objects;
      for (const auto& name : groups[g].second)
        objects.push_back(modelByName(name));
      const fs::path model_path = opt.out / "models" / (objects[0].name + ".ply");
      if (pcl::io::savePLYFileBinary(model_path.string(), objects[0].mesh) != 0)
        throw std::runtime_error("cannot write " + model_path.string());
      for (int k = 0; k < opt.cases; ++k) {
        const std::uint64_t seed = opt.seed + 1000 * g + static_cast<std::uint64_t>(k);
        Case c = opt.kind == "views" ? makeView(objects[0], seed) : makeTabletop(objects, seed);
        char name[128];
        std::snprintf(name, sizeof(name), "%s_%03d", groups[g].first.c_str(), k);
        const fs::path scene_path = opt.out / opt.kind / (std::string(name) + ".pcd");
        if (pcl::io::savePCDFileBinaryCompressed(scene_path.string(), *c.cluster) != 0)
          throw std::runtime_error("cannot write " + scene_path.string());
        manifest << "name=" << name << " group=" << groups[g].first
                 << " scene=" << fs::relative(scene_path, base).string()
                 << " model=" << fs::relative(model_path, base).string()
                 << " units=m truth=" << truthSpec(c.truth)
                 << " symmetry=" << symmetrySpec(objects[0].name) << " cluster=all\n";
        ++written;
        if (tty)
          std::fprintf(stderr, "\r[%zu/%zu] %s (%zu points)   ", written,
                       groups.size() * static_cast<std::size_t>(opt.cases), name,
                       c.cluster->size());
      }
    }
    if (tty)
      std::fprintf(stderr, "\n");
    std::printf("wrote %zu cases in %zu groups to %s, manifest %s\n", written, groups.size(),
                opt.out.string().c_str(), opt.manifest.string().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcl_icf_make_dataset: %s\n", e.what());
    return 2;
  }
  return 0;
}
