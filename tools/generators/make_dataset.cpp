// pcl_icf_make_dataset: writes a seeded synthetic benchmark suite for pcl_icf_bench — the
// thesis's models (chapter 6-7) seen by a simulated Kinect — and its manifest
// (doc/DATASETS.md).
//
//   pcl_icf_make_dataset --out DIR [--manifest FILE]
//                        [--kind views|tabletop|absent|present|clutter|sequence] [--cases N]
//                        [--frames N] [--models A,B,...] [--seed S]
//
// --kind views (default): per model N single-object clusters, the model at a uniformly random
//   rotation, x, y in [-0.15, 0.15] m and 0.7-1.1 m in front of the camera (the synthetic library's
//   randomTabletopPose), rendered alone (renderCluster); groups are the model names. --models
//   may also name mesh files (.ply, .obj or .stl, metres: e.g. ../shared/data/meshes/bunny.ply),
//   free-form objects the thesis's primitives do not cover: the group is the file's stem, its
//   symmetry none.
// --kind tabletop: the thesis's scenarios 1, 2, 3 and 5 (section 6.2) rebuilt: the target and
//   its neighbours stand upright at random non-overlapping places on a table seen from
//   0.5-0.8 m above at 35-60 degrees (makeTabletopScene); the cluster is the target's own
//   pixels (an oracle segmentation, occlusion by the neighbours included). Groups S1-Box5
//   (with a cup and the statue), S2-Box5 (with a larger box), S3-YellowRoundSalt (with Box5),
//   S5-Amicelly and S5-EisKaffe (the two together). --models filters by target model.
// --kind absent: target-absent table tops. The same scenes, but the asked-for model is NOT on
//   the table: a similar shape (the decoy) stands there instead, with neighbours. Groups
//   A-TallCylinder (a shorter, wider cylinder), A-Box5 (a box of other proportions),
//   A-Amicelly (YellowRoundSalt, a cylinder), A-EisKaffe (YellowRoundSalt), A-YellowRoundSalt
//   (EisKaffe). The scene file is the whole organized frame with colour, table included; the
//   manifest line says truth=none cluster=all. --models filters by target model.
// --kind present: the absent kind's scenes with the target put back: the target, its decoy
//   (the similar shape, same colour) and the neighbours, the whole organized frame. Groups
//   P-TallCylinder, P-Box5, P-Amicelly, P-EisKaffe, P-YellowRoundSalt; the manifest line has
//   the target's truth and cluster=all (for icf-scene: find the right one of two look-alikes).
// --kind clutter: N cluttered desks (synthetic::makeClutterScene): 10-25 objects of
//   every model but the target's, most touching a neighbour, some standing on a box or a can,
//   2-5 more on a shelf behind the desk's far edge, seen from 0.5-0.8 m above at 35-60 degrees
//   with Kinect v1 edge artefacts (holes and flying pixels along depth edges) besides the noise;
//   the target (the four thesis models in turn, --models filters) 30-50%, 50-75% and 75-100%
//   visible in turn (desk k: band k mod 3; of its part inside the frame), 15% of the time on
//   top of another object. Each desk gives two cases, whole organized frames (cluster=all):
//   K_NNN with the target, in group K-v0-30, K-v30-50, K-v50-75 or K-v75-100 by the share of
//   the whole target seen (ClutterScene::wholeTargetVisible: a target partly beyond the
//   frame's border is that much less visible; results per visibility band), and
//   K_NNN_absent, the same desk with the target taken away (truth=none, group K-absent). Desk k
//   draws from seed + k.
// --kind desk: the clutter kind as a real desk: 15-25 objects, the camera 0.5-1.1 m above at
//   35-60 degrees (the target 0.6-1.6 m away), Kinect v1 structured-light noise (quantised
//   disparity, synthetic::ScanNoise::structuredLight) and edge artefacts, the target 25-50%,
//   50-75% and 75-100% visible in turn. D_NNN and D_NNN_absent; groups by range and the share of
//   the whole target seen (D-r0.6-0.9-v25-50, ..., D-absent).
// --kind sequence: N streams of --frames organized frames (doc/DATASETS.md) for the tracker
//   (pcl_icf_tool --track): two of the thesis models (drawn per sequence) tracked, the first
//   moving along a smooth curve and taken off the table for 3-6 frames, then put back where
//   its path has carried on; the second moving slowly behind the path of an untracked
//   occluder (TallCylinder) that crosses in front of it mid-sequence. Writes per sequence
//   DIR/sequence/seq_<k>/frames/frame_<f>.pcd, frames.txt (the list, in order), truth.json
//   (per frame and object: present, visible fraction, pose) and tracked_models.txt (the
//   tracked models' paths, relative to the sequence); no manifest.
// Noise everywhere: 1.5 mm at 1 m growing with depth^2, 5% outliers within +-5 cm along the
// ray (synthetic::ScanNoise defaults). Case k of a group draws from std::mt19937_64 seeded with
// seed + 1000 * group + k, so adding cases never changes the earlier ones.
//
// Writes DIR/models/<Model>.ply (binary PLY, metres), DIR/<kind>/<case>.pcd (binary_compressed PCD,
// camera at the origin: PointXYZ clusters, or for absent, present and clutter organized 640x480
// PointXYZRGB frames
// with NaN where nothing was hit) and the manifest (default DIR/manifest.txt) whose paths are
// relative to the manifest's directory. Exit codes: 0 written, 2 bad usage or I/O error.
#include "common/arguments.h"
#include "synthetic/depth_camera.h"
#include "synthetic/mesh_geometry.h"
#include "synthetic/pose_error.h"
#include "synthetic/synthetic_clutter.h"
#include "synthetic/synthetic_models.h"
#include "synthetic/synthetic_sequence.h"

#include <pcl/icf/io/mesh_io.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <nlohmann/json.hpp>

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
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;
namespace t = pcl::icf::synthetic;

struct Options {
  fs::path out;
  fs::path manifest;
  std::string kind = "views";
  int cases = -1;                   ///< -1: the kind's default (30; sequence: 1)
  int frames = 40;                  ///< sequence: frames per sequence
  std::vector<std::string> models;  ///< empty: every model (views: the four thesis models)
  std::uint64_t seed = 2013;
};

/** How a kind of suite is written. */
enum class Writer {
  Groups,    ///< per group of the kind (allGroups), cases per group (writeSuite)
  Desks,     ///< cluttered desks, each with its target-absent twin (writeClutterSuite)
  Sequences  ///< streams of frames for pcl_icf_tool --track, no manifest (writeSequences)
};

/** A kind of suite: its name, its default --cases, how it is written, and what its manifest
 * says of it beyond the common header ("" nothing). */
struct Kind {
  const char* name;
  int default_cases;
  Writer writer;
  const char* header;
};

const Kind kKinds[] = {
    {"views", 30, Writer::Groups, ""},
    {"tabletop", 30, Writer::Groups, ""},
    {"absent", 30, Writer::Groups,
     "# TARGET ABSENT (truth=none): each scene is a whole organized frame (x y z rgb, table\n"
     "# included) holding a shape similar to the asked-for model, never the model itself.\n"
     "# A pose claimed here is a false pose. For the scene-level method:\n"
     "#   pcl_icf_bench --methods icf-scene --tuning depth_systematic=0 THIS_MANIFEST\n"
     "# (cluster=all is the whole frame: the cluster methods are not run on these cases).\n"},
    {"present", 30, Writer::Groups,
     "# TARGET PRESENT beside a similar shape of its colour: each scene is a whole organized\n"
     "# frame (x y z rgb, table included). For the scene-level method:\n"
     "#   pcl_icf_bench --methods icf-scene --tuning depth_systematic=0 THIS_MANIFEST\n"},
    {"clutter", 30, Writer::Desks,
     "# CLUTTERED DESKS: 10-25 objects touching, stacked, more on a shelf behind;\n"
     "# Kinect v1 holes and flying pixels along depth edges. Whole organized frames (x y z\n"
     "# rgb). K_NNN: the target's part in view 30-100% visible, group by the share of the\n"
     "# whole target seen, the part beyond the frame unseen (K-v0-30, K-v30-50, K-v50-75,\n"
     "# K-v75-100); K_NNN_absent: the same desk without it (truth=none, a pose is false).\n"
     "#   pcl_icf_bench --methods icf-scene --tuning depth_systematic=0 THIS_MANIFEST\n"},
    {"desk", 30, Writer::Desks,
     "# REAL-LIKE DESKS: 15-25 objects touching, stacked, more on a shelf behind, the target\n"
     "# 0.6-1.6 m away; Kinect v1 structured-light noise (quantised disparity) and edge\n"
     "# artefacts. D_NNN: groups by range and the share of the whole target seen\n"
     "# (D-r0.6-0.9-v50-75, ...); D_NNN_absent: the same desk without it (truth=none).\n"
     "#   pcl_icf_bench --methods icf-scene --tuning depth_systematic=0 THIS_MANIFEST\n"},
    {"sequence", 1, Writer::Sequences, ""},
};

/** The kind named \a name; std::invalid_argument listing the kinds when there is none. */
const Kind& kindNamed(const std::string& name) {
  std::string names;
  for (const Kind& k : kKinds) {
    if (name == k.name)
      return k;
    names += std::string(names.empty() ? "" : ", ") + k.name;
  }
  throw std::invalid_argument("--kind must be one of " + names + ", not " + name);
}

int usage(const char* program) {
  std::string kinds;
  for (const Kind& k : kKinds)
    kinds += std::string(kinds.empty() ? "" : "|") + k.name;
  std::fprintf(stderr,
               "Usage: %s --out DIR [--manifest FILE]\n"
               "          [--kind %s]\n"
               "          [--cases N]"
               " [--frames N] [--models A,B,...] [--seed S]\n"
               "Writes a seeded synthetic suite of the thesis's models and its manifest\n"
               "(format: doc/DATASETS.md). Defaults: views, 30 cases per group, every model\n"
               "(views: the four thesis models), seed 2013, manifest DIR/manifest.txt.\n"
               "--kind clutter writes N cluttered desks (default 30), each with the target and\n"
               "its target-absent twin; --kind desk the same as a real desk (15-25 objects,\n"
               "0.6-1.6 m, structured-light noise), grouped by range and visibility.\n"
               "--kind sequence writes N (default 1) streams of --frames (default 40) frames\n"
               "for pcl_icf_tool --track, each with frames.txt and truth.json, no manifest.\n",
               program, kinds.c_str());
  return 2;
}

/** The options; std::invalid_argument on a bad one. False for --help. */
bool parseOptions(int argc, char** argv, Options& opt) {
  using namespace pcl_icf_tools;
  ArgumentReader args(argc, argv);
  while (!args.done()) {
    const std::string arg = args.next();
    if (arg == "--out")
      opt.out = args.value(arg);
    else if (arg == "--manifest")
      opt.manifest = args.value(arg);
    else if (arg == "--kind")
      opt.kind = args.value(arg);
    else if (arg == "--cases")
      opt.cases = static_cast<int>(std::clamp(parseInteger(arg, args.value(arg)), 0LL, 1000000LL));
    else if (arg == "--frames")
      opt.frames =
          static_cast<int>(std::clamp(parseInteger(arg, args.value(arg)), -1LL, 1000000LL));
    else if (arg == "--models")
      opt.models = splitComma(args.value(arg));
    else if (arg == "--seed") {
      const std::string text = args.value(arg);
      const long long seed = parseInteger(arg, text);
      if (seed < 0)
        throw UsageError(arg + ": '" + text + "' is not an integer");
      opt.seed = static_cast<std::uint64_t>(seed);
    } else if (arg == "-h" || arg == "--help")
      return false;
    else
      throw UsageError("unknown option " + arg);
  }
  if (opt.out.empty())
    throw std::invalid_argument("--out is required");
  const Kind& kind = kindNamed(opt.kind);
  if (opt.cases == -1)
    opt.cases = kind.default_cases;
  if (opt.cases < 1 || opt.cases > 100000)
    throw std::invalid_argument("--cases must lie in [1, 100000]");
  if (opt.frames < 10 || opt.frames > 100000)
    throw std::invalid_argument("--frames must lie in [10, 100000]");
  if (kind.writer == Writer::Sequences && (!opt.manifest.empty() || !opt.models.empty()))
    throw std::invalid_argument("--kind sequence takes no --manifest and no --models");
  if (opt.manifest.empty())
    opt.manifest = opt.out / "manifest.txt";
  return true;
}

/** The manifest's symmetry spec of a model (doc/DATASETS.md), from its name. */
/** Whether a --models entry names a mesh file rather than a built-in model. */
bool isMeshFile(const std::string& name) {
  const std::string ext = fs::path(name).extension().string();
  return ext == ".ply" || ext == ".obj" || ext == ".stl";
}

std::string symmetrySpec(const std::string& name) {
  if (isMeshFile(name))
    return "none";
  static const std::map<std::string, std::string> specs = {
      {"Box5", "box:0.14,0.09,0.05"}, {"YellowRoundSalt", "cylinder"},  {"EisKaffe", "cylinder"},
      {"Amicelly", "prism:6"},        {"Cup", "cylinder:noflip"},       {"Statue", "none"},
      {"TallCylinder", "cylinder"},   {"LargeBox", "box:0.2,0.12,0.08"}};
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

/** A model of the suites by name (synthetic::suiteModel), or a mesh file's (no symmetry). */
t::SyntheticModel modelByName(const std::string& name) {
  if (!isMeshFile(name))
    return t::suiteModel(name);
  t::SyntheticModel m;
  m.name = name;
  m.mesh = pcl::icf::io::loadPolygonMesh(name);  // throws, naming the file, when unreadable
  pcl::PointCloud<pcl::PointXYZ> vertices;       // only x y z (a scan's extra fields dropped)
  pcl::fromPCLPointCloud2(m.mesh.cloud, vertices);
  pcl::toPCLPointCloud2(vertices, m.mesh.cloud);
  m.symmetry = t::Symmetry::none();
  return m;
}

/** A group of a suite: its name, the target model, the objects on the table. */
struct Group {
  std::string name, target;
  std::vector<std::string> objects;  ///< views, tabletop: the target first; absent: no target
};

std::vector<Group> allGroups(const std::string& kind) {
  if (kind == "views") {
    std::vector<Group> groups;
    for (const char* m : {"Box5", "YellowRoundSalt", "EisKaffe", "Amicelly"})
      groups.push_back({m, m, {m}});
    return groups;
  }
  if (kind == "tabletop")
    return {{"S1-Box5", "Box5", {"Box5", "Cup", "Statue"}},
            {"S2-Box5", "Box5", {"Box5", "LargeBox"}},
            {"S3-YellowRoundSalt", "YellowRoundSalt", {"YellowRoundSalt", "Box5"}},
            {"S5-Amicelly", "Amicelly", {"Amicelly", "EisKaffe"}},
            {"S5-EisKaffe", "EisKaffe", {"EisKaffe", "Amicelly"}}};
  // absent: the decoy first (the redraw rule watches it), then the neighbours.
  std::vector<Group> groups = {
      {"A-TallCylinder", "TallCylinder", {"WideCylinder", "Box5", "Cup"}},
      {"A-Box5", "Box5", {"OtherBox", "Cup", "Statue"}},
      {"A-Amicelly", "Amicelly", {"YellowRoundSalt", "Statue"}},
      {"A-EisKaffe", "EisKaffe", {"YellowRoundSalt", "Box5", "Statue"}},
      {"A-YellowRoundSalt", "YellowRoundSalt", {"EisKaffe", "Box5", "Cup"}}};
  if (kind == "present")  // the target first, then the absent kind's decoy and neighbours
    for (Group& g : groups) {
      g.name[0] = 'P';
      g.objects.insert(g.objects.begin(), g.target);
    }
  return groups;
}

/** The kind's groups whose target --models names (all without --models; views: in its
 * order). */
std::vector<Group> selectedGroups(const Options& opt) {
  std::vector<Group> groups;
  if (opt.kind == "views" && !opt.models.empty()) {
    for (const auto& m : opt.models)
      groups.push_back({isMeshFile(m) ? fs::path(m).stem().string() : m, m, {m}});
    return groups;
  }
  for (const auto& g : allGroups(opt.kind))
    if (opt.models.empty() ||
        std::find(opt.models.begin(), opt.models.end(), g.target) != opt.models.end())
      groups.push_back(g);
  return groups;
}

struct Case {
  std::string model;
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  bool absent = false;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cluster;   ///< views, tabletop
  pcl::PointCloud<pcl::PointXYZRGB>::Ptr scene;  ///< absent, present: the whole frame
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

/** Random (x, y, yaw) on the table for objects of these bounding-circle radii, at least 2 cm
 * apart (the last draw when 1000 fail). */
std::vector<Eigen::Vector3d> placeObjects(const std::vector<double>& radius, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> x(-0.25, 0.25), y(-0.15, 0.15), yaw(-M_PI, M_PI);
  std::vector<Eigen::Vector3d> placement;
  for (std::size_t i = 0; i < radius.size(); ++i) {
    Eigen::Vector3d p;
    bool free = false;
    for (int attempt = 0; attempt < 1000 && !free; ++attempt) {
      p = Eigen::Vector3d(x(rng), y(rng), yaw(rng));
      free = true;
      for (std::size_t j = 0; j < placement.size(); ++j)
        free = free && (p.head<2>() - placement[j].head<2>()).norm() > radius[i] + radius[j] + 0.02;
    }
    placement.push_back(p);
  }
  return placement;
}

/** The objects upright on the table at random places at least 2 cm apart (bounding circles),
 * seen from a random height and tilt; redrawn while objects[0] shows fewer than 200 points. */
t::TabletopScene drawTabletop(const std::vector<t::SyntheticModel>& objects, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> height(0.5, 0.8), tilt(35.0, 60.0);
  std::vector<double> radius;
  for (const auto& o : objects) {
    const Eigen::AlignedBox3d box = t::boundingBox(o.mesh);
    radius.push_back(0.5 * (box.max() - box.min()).head<2>().norm());
  }
  for (;;) {
    const std::vector<Eigen::Vector3d> placement = placeObjects(radius, rng);
    t::ScanNoise noise;
    noise.seed = rng();
    const double h = height(rng), a = tilt(rng);
    t::TabletopScene scene =
        t::makeTabletopScene(objects, placement, t::CameraIntrinsics(), noise, h, a);
    if (t::extractLabelCloud(scene.scan, 1)->size() >= 200)
      return scene;
  }
}

/** The target (objects[0]) among its neighbours (and, for "present", its look-alike) on a
 * table top: "tabletop" (a thesis scenario) keeps the target's own pixels as the cluster,
 * "present" the whole frame. */
Case makeTabletop(const std::vector<t::SyntheticModel>& objects, std::uint64_t seed,
                  bool whole_frame) {
  const t::TabletopScene scene = drawTabletop(objects, seed);
  Case c;
  c.model = objects[0].name;
  c.truth = scene.poses[0];
  if (whole_frame)
    c.scene = scene.scan.cloud;
  else
    c.cluster = t::extractLabelCloud(scene.scan, 1);
  return c;
}

/** A target-absent scene: the decoy (objects[0]) and the neighbours, the whole frame. */
Case makeAbsent(const std::string& target, const std::vector<t::SyntheticModel>& objects,
                std::uint64_t seed) {
  Case c;
  c.model = target;
  c.absent = true;
  c.scene = drawTabletop(objects, seed).scan.cloud;
  return c;
}

Case makeCase(const Options& opt, const Group& g, const std::vector<t::SyntheticModel>& objects,
              std::uint64_t seed) {
  if (opt.kind == "views")
    return makeView(objects[0], seed);
  if (opt.kind == "tabletop" || opt.kind == "present")
    return makeTabletop(objects, seed, opt.kind == "present");
  return makeAbsent(g.target, objects, seed);
}

/** " --models A,B" as given, or nothing when every model was written. */
std::string modelsOption(const Options& opt) {
  std::string text;
  for (const auto& m : opt.models)
    text += (text.empty() ? " --models " : ",") + m;
  return text;
}

std::string manifestHeader(const Options& opt) {
  std::string text =
      "# pcl_icf bench manifest v1 (doc/DATASETS.md)\n# written by: "
      "pcl_icf_make_dataset --kind " +
      opt.kind + " --cases " + std::to_string(opt.cases) + " --seed " + std::to_string(opt.seed) +
      modelsOption(opt) +
      "\n# Simulated Kinect (640x480, f 525 px), noise 1.5 mm at 1 m ~ depth^2, 5% "
      "outliers within +-5 cm; scenes in metres, camera at the origin.\n";
  text += kindNamed(opt.kind).header;
  return text;
}

/** Writes the case's cloud and returns its manifest line. */
std::string writeCase(const Options& opt, const Group& g, const Case& c, const std::string& name,
                      const fs::path& model_path, const fs::path& base) {
  const fs::path scene_path = opt.out / opt.kind / (name + ".pcd");
  const int status = c.scene
                         ? pcl::io::savePCDFileBinaryCompressed(scene_path.string(), *c.scene)
                         : pcl::io::savePCDFileBinaryCompressed(scene_path.string(), *c.cluster);
  if (status != 0)
    throw std::runtime_error("cannot write " + scene_path.string());
  std::string line = "name=" + name + " group=" + g.name +
                     " scene=" + fs::relative(scene_path, base).string() +
                     " model=" + fs::relative(model_path, base).string() + " units=m truth=";
  if (c.absent)
    return line + "none cluster=all\n";
  return line + truthSpec(c.truth) + " symmetry=" + symmetrySpec(c.model) + " cluster=all\n";
}

/** Creates the suite's folders, opens \a manifest on opt.manifest with its header written, and
 * returns the folder its paths are relative to. */
fs::path openSuite(const Options& opt, std::ofstream& manifest) {
  const fs::path base =
      opt.manifest.parent_path().empty() ? fs::path(".") : opt.manifest.parent_path();
  for (const fs::path& dir : {opt.out / "models", opt.out / opt.kind, base})
    fs::create_directories(dir);
  manifest.open(opt.manifest);
  if (!manifest)
    throw std::runtime_error("cannot write " + opt.manifest.string());
  manifest << manifestHeader(opt);
  return base;
}

/** Every case of every group, written with its manifest; the number of cases. */
std::size_t writeSuite(const Options& opt, const std::vector<Group>& groups) {
  std::ofstream manifest;
  const fs::path base = openSuite(opt, manifest);
  const bool tty = isatty(STDERR_FILENO);
  std::size_t written = 0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    std::vector<t::SyntheticModel> objects;
    for (const auto& name : groups[g].objects)
      objects.push_back(modelByName(name));
    const std::string& target = groups[g].target;
    const fs::path model_path =
        opt.out / "models" / ((isMeshFile(target) ? groups[g].name : target) + ".ply");
    // The target is objects[0] except in the absent kind, where it is not on the table.
    const pcl::PolygonMesh target_mesh =
        objects.front().name == target ? objects.front().mesh : modelByName(target).mesh;
    if (pcl::io::savePLYFileBinary(model_path.string(), target_mesh) != 0)
      throw std::runtime_error("cannot write " + model_path.string());
    for (int k = 0; k < opt.cases; ++k) {
      const std::uint64_t seed = opt.seed + 1000 * g + static_cast<std::uint64_t>(k);
      const Case c = makeCase(opt, groups[g], objects, seed);
      char name[128];
      std::snprintf(name, sizeof(name), "%s_%03d", groups[g].name.c_str(), k);
      manifest << writeCase(opt, groups[g], c, name, model_path, base);
      ++written;
      if (tty)
        std::fprintf(stderr, "\r[%zu/%zu] %s (%zu points)   ", written,
                     groups.size() * static_cast<std::size_t>(opt.cases), name,
                     c.scene ? c.scene->size() : c.cluster->size());
    }
  }
  if (tty)
    std::fprintf(stderr, "\n");
  return written;
}

/** The band of a target whose whole is \a visible seen (ClutterScene::wholeTargetVisible): a
 * desk drawn for 30-50% of the target's part in view may show less of the whole. */
std::string visibilityBand(double visible) {
  return visible < 0.3    ? "K-v0-30"
         : visible < 0.5  ? "K-v30-50"
         : visible < 0.75 ? "K-v50-75"
                          : "K-v75-100";
}

/** A desk's group: the target's range band (0.3 m wide from 0.6 m) and visibility band. */
std::string deskGroup(double range, double visible) {
  const int band = std::clamp(static_cast<int>(std::floor((range - 0.6) / 0.3)), 0, 3);
  const char* ranges[4] = {"0.6-0.9", "0.9-1.2", "1.2-1.5", "1.5-1.8"};
  const char* visibility = visible < 0.25   ? "v0-25"
                           : visible < 0.5  ? "v25-50"
                           : visible < 0.75 ? "v50-75"
                                            : "v75-100";
  return std::string("D-r") + (range < 0.6 ? "0-0.6" : ranges[band]) + "-" + visibility;
}

/** --kind clutter (and desk): opt.cases desks, desk k from seed + k with target k mod the targets
 * (the thesis models, or --models), each written with and without its target. */
std::size_t writeClutterSuite(const Options& opt) {
  std::vector<std::string> targets = opt.models.empty() ? t::thesisModelNames() : opt.models;
  const std::vector<std::string> pool = {
      "Box5",   "EisKaffe", "YellowRoundSalt", "Amicelly",     "Cup",
      "Statue", "LargeBox", "OtherBox",        "TallCylinder", "WideCylinder"};
  for (const auto& target : targets)
    if (isMeshFile(target) || std::find(pool.begin(), pool.end(), target) == pool.end())
      throw std::invalid_argument("--kind clutter: unknown target model " + target);
  std::ofstream manifest;
  const fs::path base = openSuite(opt, manifest);
  // Every model built once; each target's mesh written once, its distractors listed once.
  std::map<std::string, t::SyntheticModel> models;
  for (const auto& name : pool)
    models[name] = modelByName(name);
  std::map<std::string, std::vector<t::SyntheticModel>> distractors_of;
  for (const auto& target : targets) {
    const fs::path model_path = opt.out / "models" / (target + ".ply");
    if (pcl::io::savePLYFileBinary(model_path.string(), models.at(target).mesh) != 0)
      throw std::runtime_error("cannot write " + model_path.string());
    for (const auto& name : pool)
      if (name != target)
        distractors_of[target].push_back(models.at(name));
  }
  const bool tty = isatty(STDERR_FILENO);
  for (int k = 0; k < opt.cases; ++k) {
    const std::string& target = targets[static_cast<std::size_t>(k) % targets.size()];
    const std::vector<t::SyntheticModel>& distractors = distractors_of.at(target);
    const t::SyntheticModel& model = models.at(target);
    const fs::path model_path = opt.out / "models" / (target + ".ply");
    // Visibility bands in turn with the targets (k mod 3: 30-50%, 50-75%, 75-100%): a desk
    // drawn freely hides its target less than half the time.
    const bool desk = opt.kind == "desk";
    t::ClutterSpec spec;
    const double band_edges[4] = {desk ? 0.25 : 0.3, 0.5, 0.75, 1.0};
    spec.min_target_visible = band_edges[k % 3];
    spec.max_target_visible = band_edges[k % 3 + 1];
    if (desk) {
      spec.min_objects = 15;
      spec.max_objects = 25;
      spec.camera_min_height = 0.5;
      spec.camera_max_height = 1.1;
      spec.noise = t::ScanNoise::structuredLight();
    }
    const t::ClutterScene scene =
        t::makeClutterScene(model, distractors, opt.seed + static_cast<std::uint64_t>(k), spec);
    char name[32];
    std::snprintf(name, sizeof(name), desk ? "D_%03d" : "K_%03d", k);
    const std::string model_rel = fs::relative(model_path, base).string();
    for (const bool absent : {false, true}) {
      const std::string case_name = std::string(name) + (absent ? "_absent" : "");
      const fs::path scene_path = opt.out / opt.kind / (case_name + ".pcd");
      if (pcl::io::savePCDFileBinaryCompressed(scene_path.string(),
                                               *(absent ? scene.absent : scene.present).cloud) != 0)
        throw std::runtime_error("cannot write " + scene_path.string());
      const std::string group =
          desk ? (absent
                      ? std::string("D-absent")
                      : deskGroup(scene.poses[0].translation().norm(), scene.wholeTargetVisible()))
               : (absent ? std::string("K-absent") : visibilityBand(scene.wholeTargetVisible()));
      manifest << "name=" << case_name << " group=" << group
               << " scene=" << fs::relative(scene_path, base).string() << " model=" << model_rel
               << " units=m truth="
               << (absent ? std::string("none")
                          : truthSpec(scene.poses[0]) + " symmetry=" + symmetrySpec(target))
               << " cluster=all\n";
    }
    if (tty)
      std::fprintf(stderr, "\r[%d/%d] %s: %s, %zu objects, %.0f%% visible   ", k + 1, opt.cases,
                   name, target.c_str(), scene.names.size(), 100.0 * scene.wholeTargetVisible());
  }
  if (tty)
    std::fprintf(stderr, "\n");
  if (!manifest)
    throw std::runtime_error("cannot write " + opt.manifest.string());
  return 2 * static_cast<std::size_t>(opt.cases);
}

/** Sequence k's objects: two distinct thesis models tracked, A moving along a smooth curve at
 * the back of the table and taken away for 3-6 frames in its first half, B moving slowly in
 * front, and an untracked TallCylinder (the occluder) crossing in front of B around the
 * middle frame. The camera looks from the -y side (makeTabletopScene), so y orders depth. */
t::SequenceSpec drawSequence(int frames, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  // One draw per statement: the order of draws must not depend on the compiler's order of
  // evaluating arguments.
  auto uniform = [&rng](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  auto sign = [&rng]() { return std::bernoulli_distribution(0.5)(rng) ? 1.0 : -1.0; };
  std::vector<std::string> names = t::thesisModelNames();
  std::shuffle(names.begin(), names.end(), rng);
  const double n = static_cast<double>(frames), deg = M_PI / 180.0;
  t::SequenceSpec spec;
  spec.frames = frames;
  spec.noise.seed = rng();

  t::SequenceObject a, b, occluder;
  a.model = modelByName(names[0]);
  const double travel = uniform(0.25, 0.4);  // metres along x over the sequence
  a.start.x() = -0.5 * travel;
  a.start.y() = uniform(0.13, 0.17);
  a.start.z() = uniform(-M_PI, M_PI);
  a.velocity.x() = travel / n;
  a.velocity.z() = sign();
  a.velocity.z() *= uniform(1.0, 3.0) * deg;
  a.sway.y() = uniform(0.01, 0.03);
  a.sway_period = uniform(0.5, 1.0) * n;
  a.absent_from = std::uniform_int_distribution<int>(frames / 5, frames / 2)(rng);
  a.absent_until = a.absent_from + std::uniform_int_distribution<int>(3, 6)(rng);

  b.model = modelByName(names[1]);
  b.start.x() = uniform(-0.05, 0.05);
  b.start.y() = uniform(-0.05, -0.02);
  b.start.z() = uniform(-M_PI, M_PI);
  b.velocity.x() = sign();
  b.velocity.x() *= uniform(0.0, 0.002);
  b.velocity.z() = sign();
  b.velocity.z() *= uniform(0.0, 1.0) * deg;

  occluder.model = modelByName("TallCylinder");
  occluder.tracked = false;
  const double speed = uniform(0.012, 0.018);
  const double direction = sign();
  occluder.start.x() = b.placement(frames / 2).x() - direction * speed * 0.5 * n;
  occluder.start.y() = uniform(-0.19, -0.17);
  occluder.velocity.x() = direction * speed;
  spec.objects = {a, b, occluder};
  return spec;
}

nlohmann::ordered_json poseJson(const Eigen::Isometry3d& pose) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (int r = 0; r < 4; ++r)
    rows.push_back({pose(r, 0), pose(r, 1), pose(r, 2), pose(r, 3)});
  return rows;
}

/** Writes sequence \a name into DIR/sequence/NAME: frames/, frames.txt, truth.json. */
void writeSequence(const Options& opt, const t::SequenceSpec& spec, const std::string& name,
                   std::uint64_t seed, bool tty) {
  const fs::path dir = opt.out / "sequence" / name;
  fs::create_directories(dir / "frames");
  nlohmann::ordered_json truth;
  truth["format"] = "pcl_icf sequence truth v1 (doc/DATASETS.md)";
  truth["written_by"] = "pcl_icf_make_dataset --kind sequence --frames " +
                        std::to_string(opt.frames) + " --seed " + std::to_string(opt.seed);
  truth["seed"] = seed;
  truth["units"] = "m";
  const t::CameraIntrinsics& k = spec.intrinsics;
  truth["camera"] = {{"width", k.width}, {"height", k.height}, {"fx", k.fx},
                     {"fy", k.fy},       {"cx", k.cx},         {"cy", k.cy}};
  std::ofstream tracked(dir / "tracked_models.txt");  // the models to give pcl_icf_tool --track
  for (const auto& o : spec.objects) {
    if (o.tracked)
      tracked << fs::relative(opt.out / "models" / (o.model.name + ".ply"), dir).string() << "\n";
    nlohmann::ordered_json j;
    j["name"] = o.model.name;
    j["model"] = fs::relative(opt.out / "models" / (o.model.name + ".ply"), dir).string();
    j["symmetry"] = symmetrySpec(o.model.name);
    j["tracked"] = o.tracked;
    if (o.absent_from >= 0)
      j["absent"] = {o.absent_from, o.absent_until};
    truth["objects"].push_back(j);
  }
  std::ofstream list(dir / "frames.txt");
  list << "# " << name << ": " << spec.frames << " frames in order (truth.json)\n";
  for (int f = 0; f < spec.frames; ++f) {
    const t::SequenceFrame frame = t::renderSequenceFrame(spec, f);
    char file[64];
    std::snprintf(file, sizeof(file), "frames/frame_%04d.pcd", f);
    if (pcl::io::savePCDFileBinaryCompressed((dir / file).string(), *frame.scene.scan.cloud) != 0)
      throw std::runtime_error("cannot write " + (dir / file).string());
    list << file << "\n";
    nlohmann::ordered_json line;
    line["frame"] = f;
    line["file"] = file;
    for (std::size_t i = 0; i < spec.objects.size(); ++i)
      line["objects"].push_back({{"name", spec.objects[i].model.name},
                                 {"present", static_cast<bool>(frame.present[i])},
                                 {"visible", std::round(1e4 * frame.visible[i]) / 1e4},
                                 {"pose", poseJson(frame.poses[i])}});
    truth["frames"].push_back(line);
    if (tty)
      std::fprintf(stderr, "\r%s: frame %d/%d   ", name.c_str(), f + 1, spec.frames);
  }
  std::ofstream out(dir / "truth.json");
  out << truth.dump(1) << "\n";
  if (!list || !out || !tracked)
    throw std::runtime_error("cannot write " + dir.string());
}

/** --kind sequence: opt.cases sequences; sequence k draws from seed + k. */
std::size_t writeSequences(const Options& opt) {
  fs::create_directories(opt.out / "models");
  for (const std::string& name : t::thesisModelNames())
    if (pcl::io::savePLYFileBinary((opt.out / "models" / (name + ".ply")).string(),
                                   modelByName(name).mesh) != 0)
      throw std::runtime_error("cannot write " + (opt.out / "models").string());
  if (pcl::io::savePLYFileBinary((opt.out / "models" / "TallCylinder.ply").string(),
                                 modelByName("TallCylinder").mesh) != 0)
    throw std::runtime_error("cannot write " + (opt.out / "models").string());
  const bool tty = isatty(STDERR_FILENO);
  for (int k = 0; k < opt.cases; ++k) {
    const std::uint64_t seed = opt.seed + static_cast<std::uint64_t>(k);
    char name[32];
    std::snprintf(name, sizeof(name), "seq_%03d", k);
    writeSequence(opt, drawSequence(opt.frames, seed), name, seed, tty);
  }
  if (tty)
    std::fprintf(stderr, "\n");
  return static_cast<std::size_t>(opt.cases);
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  try {
    if (!parseOptions(argc, argv, opt))
      return usage(argv[0]) - 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcl_icf_make_dataset: %s\n", e.what());
    return usage(argv[0]);
  }
  try {
    const Writer writer = kindNamed(opt.kind).writer;
    if (writer == Writer::Sequences) {
      const std::size_t written = writeSequences(opt);
      std::printf("wrote %zu sequences of %d frames to %s\n", written, opt.frames,
                  (opt.out / "sequence").string().c_str());
      return 0;
    }
    if (writer == Writer::Desks) {
      const std::size_t written = writeClutterSuite(opt);
      std::printf("wrote %zu cases (%d desks, with and without the target) to %s, manifest %s\n",
                  written, opt.cases, opt.out.string().c_str(), opt.manifest.string().c_str());
      return 0;
    }
    const std::vector<Group> groups = selectedGroups(opt);
    if (groups.empty())
      throw std::invalid_argument("--models selects no group of --kind " + opt.kind);
    const std::size_t written = writeSuite(opt, groups);
    std::printf("wrote %zu cases in %zu groups to %s, manifest %s\n", written, groups.size(),
                opt.out.string().c_str(), opt.manifest.string().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcl_icf_make_dataset: %s\n", e.what());
    return 2;
  }
  return 0;
}
