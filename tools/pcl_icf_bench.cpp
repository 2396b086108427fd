// pcl_icf_bench: ICF against PCL's registration pipelines on the same clusters.
//
//   pcl_icf_bench [options] MANIFEST...
//     --out DIR            CSV and markdown go here (default bench_out)
//     --plots DIR          PNG bar charts go here (default: --out)
//     --name NAME          file prefix (default: the first manifest's stem)
//     --methods A,B,...    subset of the methods below (default: all)
//     --thesis-cases N     run icf-thesis on the first N cases of each group only (default 5;
//                          -1: all). It costs 10-50 s per case.
//     --limit N            at most N cases per group
//     --threads N          threads for ICF and for the feature estimation (0: all cores)
//     --ia-iterations N    SAC-IA hypotheses (default 1000)
//     --sac K=V,...        override SacParams fields for both SAC pipelines and the fallback:
//                          voxel_size, normal_radius, feature_radius, max_iterations,
//                          correspondence_randomness, similarity_threshold,
//                          max_correspondence_distance, inlier_fraction, model_samples, seed
//     --repeat N           run every method N times per case and report the median time
//                          (the poses are identical: every method is seeded); icf-thesis
//                          runs once. For small suites on a busy machine.
//     --no-plots           skip gnuplot
//
// Methods (all on the same cluster points, model prepared once per model and not timed):
//   icf-fast      pcl::IterativeClosestFace, fast global search, fallback off
//   icf-thesis    pcl::IterativeClosestFace, the thesis's stochastic search, fallback off
//   icf-fast+sac  pcl::IterativeClosestFace, fast search, SampleConsensus fallback auto (default)
//   icf-sac       pcl::IterativeClosestFace, fallback always (prerejective + ICF)
//   icp-p2p       pcl::IterativeClosestPoint from the centroid start on dense mesh samples
//   icp-p2plane   pcl::IterativeClosestPointWithNormals, same start and samples
//   sacia+icp     FPFH + pcl::SampleConsensusInitialAlignment, then pcl::IterativeClosestPoint
//   prerej+icp    FPFH + pcl::SampleConsensusPrerejective, then pcl::IterativeClosestPoint
//
// Per method: success rate (translation <= 1 cm and rotation <= 5 degrees, symmetry-aware),
// mean / median / standard deviation of the translation error (mm) and rotation error
// (degrees) as the thesis's chapter 7 reports them, ADD-S (mm: mean distance from 2000 truly posed
// surface samples to the estimated model surface) and the median time. Writes NAME_cases.csv (one
// row per case and method), NAME_summary.csv, NAME.md (also printed on stdout), the plot's data and
// gnuplot script (NAME_plot.dat/.gp) in
// --out and, with gnuplot, NAME_mean.png and NAME_std.png in --plots (bar charts per group and
// method like the thesis's figures 7.5 and 7.6). Progress goes to stderr
// when it is a terminal. Exit codes: 0 done, 2 bad usage, manifest or data.
#include "support/pose_error.h"

#include <pcl/common/centroid.h>
#include <pcl/common/transforms.h>
#include <pcl/console/print.h>
#include <pcl/features/normal_3d_omp.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/iterative_closest_face.h>
#include <pcl/icf/sample_consensus_alignment.h>
#include <pcl/io/pcd_io.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/transformation_estimation_point_to_plane_lls.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
namespace t = pcl::icf::test;
using Clock = std::chrono::steady_clock;
using CloudXYZ = pcl::PointCloud<pcl::PointXYZ>;
using CloudN = pcl::PointCloud<pcl::PointNormal>;

const std::vector<std::string> kAllMethods = {"icf-fast",  "icf-thesis", "icf-fast+sac",
                                              "icf-sac",   "icp-p2p",    "icp-p2plane",
                                              "sacia+icp", "prerej+icp"};
constexpr double kSuccessTranslation = 0.01;  // metres
constexpr double kSuccessRotation = 5.0;      // degrees

class BadInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// ---------------------------------------------------------------------------- the manifest

/** One line of a manifest (doc/DATASETS.md). */
struct CaseSpec {
  std::string name, group;
  fs::path scene, model;
  double scale = 1.0;                                       ///< model units to metres
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();  ///< model (metres) -> scene
  std::string symmetry_spec = "none";
  /** The frame the errors are measured in, in the model frame: its origin (center=) is the
   * point whose translation error counts and the symmetry's centre, its axes (axes=) the
   * symmetry's axes. Identity by default. */
  Eigen::Isometry3d reference = Eigen::Isometry3d::Identity();
  std::string cluster = "all";  ///< all | indices:FILE | crop:MARGIN
  fs::path indices;
  double crop_margin = 0.0;
  bool camera_set = false;
  Eigen::Vector3f camera = Eigen::Vector3f::Zero();
  std::string source;  ///< "manifest:line" for messages
};

std::vector<double> parseNumbers(const std::string& text, const std::string& where) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(v))
      throw BadInput(where + ": '" + item + "' is not a finite number");
    values.push_back(v);
  }
  return values;
}

t::Symmetry parseSymmetry(const std::string& spec, const std::string& where) {
  const std::string kind = spec.substr(0, spec.find(':'));
  const std::string args =
      spec.find(':') == std::string::npos ? "" : spec.substr(spec.find(':') + 1);
  if (kind == "none" && args.empty())
    return t::Symmetry::none();
  if (kind == "box") {
    const auto s = parseNumbers(args, where);
    if (s.size() != 3)
      throw BadInput(where + ": symmetry=box:SX,SY,SZ needs three sizes");
    return t::Symmetry::box(s[0], s[1], s[2]);
  }
  if (kind == "prism") {
    const auto n = parseNumbers(args, where);
    if (n.size() != 1 || n[0] < 1 || n[0] != std::floor(n[0]))
      throw BadInput(where + ": symmetry=prism:N needs a whole N >= 1");
    return t::Symmetry::prism(static_cast<int>(n[0]));
  }
  if (kind == "cylinder" && (args.empty() || args == "noflip"))
    return t::Symmetry::cylinder(args.empty());
  throw BadInput(where + ": unknown symmetry '" + spec +
                 "' (none, box:SX,SY,SZ, prism:N, cylinder, cylinder:noflip)");
}

std::vector<CaseSpec> readManifest(const fs::path& path) {
  std::ifstream in(path);
  if (!in)
    throw BadInput(path.string() + ": cannot read the manifest");
  const fs::path base = path.parent_path();
  std::vector<CaseSpec> cases;
  std::set<std::string> names;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string where = path.string() + ":" + std::to_string(number);
    const auto hash = line.find('#');
    if (hash != std::string::npos)
      line.erase(hash);
    std::stringstream tokens(line);
    std::string token;
    CaseSpec c;
    c.source = where;
    std::map<std::string, std::string> fields;
    while (tokens >> token) {
      const auto eq = token.find('=');
      if (eq == std::string::npos || eq == 0)
        throw BadInput(where + ": '" + token + "' is not key=value");
      const std::string key = token.substr(0, eq);
      if (!fields.emplace(key, token.substr(eq + 1)).second)
        throw BadInput(where + ": " + key + " given twice");
    }
    if (fields.empty())
      continue;
    for (const char* required : {"name", "scene", "model", "truth"})
      if (!fields.count(required))
        throw BadInput(where + ": missing " + required + "=");
    for (const auto& [key, value] : fields) {
      if (key == "name")
        c.name = value;
      else if (key == "group")
        c.group = value;
      else if (key == "scene")
        c.scene = base / value;
      else if (key == "model")
        c.model = base / value;
      else if (key == "units") {
        if (value == "m")
          c.scale = 1.0;
        else if (value == "mm")
          c.scale = 1e-3;
        else
          throw BadInput(where + ": units must be m or mm, not " + value);
      } else if (key == "truth") {
        const auto v = parseNumbers(value, where);
        if (v.size() != 16 && v.size() != 12)
          throw BadInput(where + ": truth needs 16 (or 12) row-major numbers");
        Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
        for (std::size_t i = 0; i < v.size(); ++i)
          m(static_cast<int>(i / 4), static_cast<int>(i % 4)) = v[i];
        const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
        if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-4 ||
            r.determinant() < 0.0)
          throw BadInput(where + ": truth's rotation is not a rotation");
        c.truth.matrix() = m;
      } else if (key == "symmetry") {
        parseSymmetry(value, where);
        c.symmetry_spec = value;
      } else if (key == "center") {
        const auto v = parseNumbers(value, where);
        if (v.size() != 3)
          throw BadInput(where + ": center needs three numbers");
        c.reference.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
      } else if (key == "axes") {
        const auto v = parseNumbers(value, where);
        if (v.size() != 9)
          throw BadInput(where + ": axes needs nine row-major numbers");
        Eigen::Matrix3d r;
        for (int i = 0; i < 9; ++i)
          r(i / 3, i % 3) = v[static_cast<std::size_t>(i)];
        if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-4 ||
            r.determinant() < 0.0)
          throw BadInput(where + ": axes is not a rotation");
        c.reference.linear() = r;
      } else if (key == "camera") {
        const auto v = parseNumbers(value, where);
        if (v.size() != 3)
          throw BadInput(where + ": camera needs three numbers");
        c.camera = Eigen::Vector3d(v[0], v[1], v[2]).cast<float>();
        c.camera_set = true;
      } else if (key == "cluster") {
        c.cluster = value;
        if (value.rfind("indices:", 0) == 0)
          c.indices = base / value.substr(8);
        else if (value.rfind("crop:", 0) == 0) {
          const auto v = parseNumbers(value.substr(5), where);
          if (v.size() != 1 || v[0] < 0.0)
            throw BadInput(where + ": cluster=crop:MARGIN needs one margin >= 0 (metres)");
          c.crop_margin = v[0];
        } else if (value != "all")
          throw BadInput(where + ": cluster must be all, indices:FILE or crop:MARGIN");
      } else
        throw BadInput(where + ": unknown key " + key);
    }
    if (!names.insert(c.name).second)
      throw BadInput(where + ": case name " + c.name + " repeats");
    if (c.group.empty())
      c.group = c.model.stem().string();
    cases.push_back(c);
  }
  return cases;
}

// ------------------------------------------------------------------------ models and data

/** Everything prepared once per model (not timed). */
struct PreparedModel {
  pcl::PolygonMesh::Ptr mesh;        ///< in metres
  pcl::icf::IcfModel::ConstPtr icf;  ///< faces, index, field, samples
  CloudXYZ::Ptr dense;               ///< 20000 area-weighted samples (ICP targets)
  CloudN::Ptr dense_normals;         ///< the same with face normals
  CloudXYZ::Ptr adds_samples;        ///< 2000 samples for ADD-S
  double icf_build_ms = 0.0, sac_build_ms = 0.0;
};

std::shared_ptr<PreparedModel> prepareModel(const fs::path& path, double scale,
                                            const pcl::icf::SacParams& sac, int threads) {
  auto m = std::make_shared<PreparedModel>();
  m->mesh = pcl::make_shared<pcl::PolygonMesh>(pcl::icf::io::loadPolygonMesh(path.string()));
  if (scale != 1.0) {
    CloudXYZ vertices;
    pcl::fromPCLPointCloud2(m->mesh->cloud, vertices);
    for (auto& p : vertices)
      p.getVector3fMap() *= static_cast<float>(scale);
    pcl::toPCLPointCloud2(vertices, m->mesh->cloud);
  }
  auto start = Clock::now();
  m->icf = pcl::icf::IcfModel::build(*m->mesh);
  m->icf_build_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  start = Clock::now();
  pcl::icf::cachedSacModel(*m->icf, sac, threads);
  m->sac_build_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  m->dense = pcl::make_shared<CloudXYZ>();
  m->dense_normals = pcl::make_shared<CloudN>();
  for (const auto& s : pcl::icf::sampleSurface(m->icf->mesh(), 20000, 11)) {
    m->dense->push_back(pcl::PointXYZ(s.point.x(), s.point.y(), s.point.z()));
    pcl::PointNormal p;
    p.getVector3fMap() = s.point;
    p.getNormalVector3fMap() = s.normal;
    m->dense_normals->push_back(p);
  }
  m->adds_samples = pcl::make_shared<CloudXYZ>();
  for (const auto& s : pcl::icf::sampleSurface(m->icf->mesh(), 2000, 13))
    m->adds_samples->push_back(pcl::PointXYZ(s.point.x(), s.point.y(), s.point.z()));
  return m;
}

/** ADD-S (metres): the mean, over the model's 2000 surface samples posed by the truth, of the
 * exact distance to the surface of the model posed by the estimate (point-to-face through the
 * model's index, so there is no sample-spacing floor: a pose that differs from the truth by a
 * symmetry scores 0). */
double addS(const PreparedModel& model, const Eigen::Isometry3d& est,
            const Eigen::Isometry3d& truth) {
  const Eigen::Isometry3f to_est_frame = (est.inverse() * truth).cast<float>();
  double sum = 0.0;
  for (const auto& p : *model.adds_samples)
    sum += model.icf->index().closestFace(to_est_frame * p.getVector3fMap()).distance;
  return sum / static_cast<double>(model.adds_samples->size());
}

/** The case's cluster: finite scene points selected by the cluster spec. */
CloudXYZ::Ptr loadCluster(const CaseSpec& c, const PreparedModel& model, Eigen::Vector3f& camera) {
  pcl::icf::io::requireReadableFile(c.scene.string());
  CloudXYZ scene;
  if (pcl::io::loadPCDFile(c.scene.string(), scene) < 0 || scene.empty())
    throw BadInput(c.source + ": " + c.scene.string() + " is not a readable PCD cloud");
  camera = c.camera_set ? c.camera : Eigen::Vector3f(scene.sensor_origin_.head<3>());
  std::vector<bool> keep(scene.size(), c.cluster == "all");
  if (!c.indices.empty()) {
    std::ifstream in(c.indices);
    if (!in)
      throw BadInput(c.source + ": cannot read " + c.indices.string());
    long long i;
    while (in >> i) {
      if (i < 0 || static_cast<std::size_t>(i) >= scene.size())
        throw BadInput(c.source + ": index " + std::to_string(i) + " outside the scene");
      keep[static_cast<std::size_t>(i)] = true;
    }
  }
  if (c.cluster.rfind("crop:", 0) == 0) {
    // Oracle crop: the ground-truth posed bounding box of the model, inflated by the margin.
    const Eigen::Isometry3f to_model = c.truth.inverse().cast<float>();
    const Eigen::Vector3f lo =
        model.icf->mesh().boundsMin() - Eigen::Vector3f::Constant(float(c.crop_margin));
    const Eigen::Vector3f hi =
        model.icf->mesh().boundsMax() + Eigen::Vector3f::Constant(float(c.crop_margin));
    for (std::size_t i = 0; i < scene.size(); ++i) {
      const Eigen::Vector3f x = to_model * scene[i].getVector3fMap();
      keep[i] = (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
    }
  }
  auto cluster = pcl::make_shared<CloudXYZ>();
  for (std::size_t i = 0; i < scene.size(); ++i)
    if (keep[i] && scene[i].getVector3fMap().allFinite())
      cluster->push_back(scene[i]);
  cluster->sensor_origin_.head<3>() = camera;
  if (cluster->size() < 10)
    throw BadInput(c.source + ": the cluster has " + std::to_string(cluster->size()) +
                   " finite points");
  return cluster;
}

// -------------------------------------------------------------------------------- methods

struct MethodRun {
  Eigen::Matrix4f object_pose = Eigen::Matrix4f::Identity();  ///< model -> scene
  double ms = 0.0;
  bool converged = false;  ///< the method's own verdict (ICF: accepted; SAC: found; ICP: PCL's)
  std::string detail;
};

/** PCL's point-to-plane LLS, except that a singular system (NaN step: PCL inverts it without a
 * rank check) gives no step instead of poisoning the cloud, which would abort in the kd-tree.
 * Otherwise stock PCL behaviour. */
class GuardedPointToPlaneLLS
    : public pcl::registration::TransformationEstimationPointToPlaneLLS<pcl::PointNormal,
                                                                        pcl::PointNormal> {
 public:
  using Base = pcl::registration::TransformationEstimationPointToPlaneLLS<pcl::PointNormal,
                                                                          pcl::PointNormal>;
  using Base::estimateRigidTransformation;
  void estimateRigidTransformation(const CloudN& source, const CloudN& target,
                                   const pcl::Correspondences& correspondences,
                                   Matrix4& transform) const override {
    Base::estimateRigidTransformation(source, target, correspondences, transform);
    if (!transform.allFinite())
      transform.setIdentity();
  }
};

Eigen::Matrix4f centroidStart(const CloudXYZ& cluster, const PreparedModel& model) {
  Eigen::Vector4f c;
  pcl::compute3DCentroid(cluster, c);
  Eigen::Matrix4f guess = Eigen::Matrix4f::Identity();
  guess.block<3, 1>(0, 3) = model.icf->mesh().surfaceCentroid() - c.head<3>();
  return guess;
}

MethodRun runIcf(const CloudXYZ::Ptr& cluster, const PreparedModel& model,
                 const pcl::icf::IcfParams& params) {
  MethodRun run;
  const auto start = Clock::now();
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputModel(model.icf);
  icf.setParams(params);
  icf.setInputSource(cluster);
  CloudXYZ aligned;
  icf.align(aligned);
  run.ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  run.object_pose = icf.getObjectPose();
  run.converged = icf.hasConverged();
  run.detail = icf.getResult().method + (icf.getResult().fallback_ran ? " (fallback ran)" : "");
  return run;
}

/** Point-to-point ICP from a scene-to-model start. */
Eigen::Matrix4f icpPointToPoint(const CloudXYZ::Ptr& cluster, const PreparedModel& model,
                                const Eigen::Matrix4f& guess, double max_distance,
                                bool& converged) {
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
  icp.setInputSource(cluster);
  icp.setInputTarget(model.dense);
  icp.setMaximumIterations(50);
  icp.setMaxCorrespondenceDistance(max_distance);
  CloudXYZ aligned;
  icp.align(aligned, guess);
  converged = icp.hasConverged();
  return icp.getFinalTransformation();
}

MethodRun runIcp(const CloudXYZ::Ptr& cluster, const PreparedModel& model, bool plane,
                 int threads) {
  MethodRun run;
  const auto start = Clock::now();
  const Eigen::Matrix4f guess = centroidStart(*cluster, model);
  Eigen::Matrix4f scene_to_model;
  if (!plane) {
    scene_to_model = icpPointToPoint(cluster, model, guess, 0.05, run.converged);
  } else {
    auto source = pcl::make_shared<CloudN>();
    pcl::copyPointCloud(*cluster, *source);
    pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::PointNormal> normals(
        static_cast<unsigned>(threads));
    normals.setInputCloud(cluster);
    normals.setRadiusSearch(0.01);
    normals.setViewPoint(cluster->sensor_origin_.x(), cluster->sensor_origin_.y(),
                         cluster->sensor_origin_.z());
    CloudN estimated;
    normals.compute(estimated);
    for (std::size_t i = 0; i < source->size(); ++i)
      (*source)[i].getNormalVector3fMap() = estimated[i].getNormalVector3fMap();
    // Points without a normal (isolated outliers) would poison the point-to-plane system.
    source->erase(std::remove_if(source->begin(), source->end(),
                                 [](const pcl::PointNormal& p) {
                                   return !p.getNormalVector3fMap().allFinite();
                                 }),
                  source->end());
    pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> icp;
    icp.setTransformationEstimation(pcl::make_shared<GuardedPointToPlaneLLS>());
    icp.setInputSource(source);
    icp.setInputTarget(model.dense_normals);
    icp.setMaximumIterations(50);
    icp.setMaxCorrespondenceDistance(0.05);
    CloudN aligned;
    icp.align(aligned, guess);
    run.converged = icp.hasConverged();
    scene_to_model = icp.getFinalTransformation();
  }
  run.ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  run.object_pose = scene_to_model.inverse();
  return run;
}

MethodRun runSacIcp(const CloudXYZ::Ptr& cluster, const PreparedModel& model,
                    const pcl::icf::SacParams& params, int threads) {
  MethodRun run;
  const auto start = Clock::now();
  std::vector<Eigen::Vector3f> points;
  points.reserve(cluster->size());
  for (const auto& p : *cluster)
    points.push_back(p.getVector3fMap());
  const auto sac = pcl::icf::sampleConsensusAlign(
      *model.icf, points, cluster->sensor_origin_.head<3>(), params, threads);
  bool icp_converged = false;
  // From SAC's pose (the identity when it found nothing: PCL's own behaviour).
  const Eigen::Matrix4f scene_to_model =
      icpPointToPoint(cluster, model, sac.scene_to_model, 0.02, icp_converged);
  run.ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  run.object_pose = scene_to_model.inverse();
  run.converged = sac.found() && icp_converged;
  run.detail =
      "sac " + pcl::icf::toString(sac.status) + ", " + std::to_string(sac.keypoints) + " keypoints";
  return run;
}

// ---------------------------------------------------------------------------- statistics

struct Row {
  std::string case_name, group, method;
  std::size_t points = 0;
  double t_mm = 0, r_deg = 0, r_nosym_deg = 0, adds_mm = 0, ms = 0;
  bool success = false, converged = false;
  std::string detail;
  Eigen::Matrix4f object_pose = Eigen::Matrix4f::Identity();  ///< the estimate, model -> scene
};

struct Summary {
  std::size_t n = 0;
  double success = 0;
  double t_mean = 0, t_median = 0, t_std = 0;
  double r_mean = 0, r_median = 0, r_std = 0;
  double adds_mean = 0, adds_median = 0, time_median = 0;
};

double median(std::vector<double> v) {
  if (v.empty())
    return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void meanStd(const std::vector<double>& v, double& mean, double& sd) {
  mean = sd = 0.0;
  if (v.empty())
    return;
  mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  double ss = 0.0;
  for (double x : v)
    ss += (x - mean) * (x - mean);
  // Sample standard deviation (n - 1), as R's sd() that drew the thesis's figures.
  sd = v.size() > 1 ? std::sqrt(ss / static_cast<double>(v.size() - 1)) : 0.0;
}

Summary summarize(const std::vector<const Row*>& rows) {
  Summary s;
  s.n = rows.size();
  std::vector<double> t, r, a, ms;
  for (const Row* row : rows) {
    t.push_back(row->t_mm);
    r.push_back(row->r_deg);
    a.push_back(row->adds_mm);
    ms.push_back(row->ms);
    s.success += row->success;
  }
  if (s.n)
    s.success /= static_cast<double>(s.n);
  meanStd(t, s.t_mean, s.t_std);
  meanStd(r, s.r_mean, s.r_std);
  double unused;
  meanStd(a, s.adds_mean, unused);
  s.t_median = median(t);
  s.r_median = median(r);
  s.adds_median = median(a);
  s.time_median = median(ms);
  return s;
}

std::string csvEscape(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos)
    return s;
  std::string out = "\"";
  for (char ch : s)
    out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return out + "\"";
}

std::string formatTable(const std::vector<std::string>& methods,
                        const std::function<std::vector<const Row*>(const std::string&)>& rowsOf) {
  std::ostringstream md;
  md << "| method | cases | success (1 cm, 5°) | t mean (mm) | t median | t std | r mean (°) "
        "| r median | r std | ADD-S mean (mm) | ADD-S median | median time (ms) |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  char line[512];
  for (const auto& m : methods) {
    const auto rows = rowsOf(m);
    if (rows.empty())
      continue;
    const Summary s = summarize(rows);
    std::snprintf(line, sizeof(line),
                  "| %s | %zu | %.0f%% | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | "
                  "%.0f |\n",
                  m.c_str(), s.n, 100.0 * s.success, s.t_mean, s.t_median, s.t_std, s.r_mean,
                  s.r_median, s.r_std, s.adds_mean, s.adds_median, s.time_median);
    md << line;
  }
  return md.str();
}

/** Bar charts like the thesis's figures 7.5 (mean) and 7.6 (standard deviation): per group
 * and method, translation error (a) above rotation error (b); log scale, since failures are
 * two orders of magnitude above successes. */
void writePlots(
    const fs::path& data_dir, const fs::path& dir, const std::string& name,
    const std::vector<std::string>& groups, const std::vector<std::string>& methods,
    const std::function<std::vector<const Row*>(const std::string&, const std::string&)>& rowsOf) {
  fs::create_directories(dir);
  fs::create_directories(data_dir);
  const fs::path data = data_dir / (name + "_plot.dat");
  {
    std::ofstream out(data);
    // Columns: group, then per method t_mean t_std r_mean r_std.
    out << "# group";
    for (const auto& m : methods)
      out << " " << m << "_tmean " << m << "_tstd " << m << "_rmean " << m << "_rstd";
    out << "\n";
    for (const auto& g : groups) {
      out << "\"" << g << "\"";
      for (const auto& m : methods) {
        const Summary s = summarize(rowsOf(g, m));
        // Floors keep zero bars drawable on the log axis.
        out << " " << std::max(s.t_mean, 0.01) << " " << std::max(s.t_std, 0.01) << " "
            << std::max(s.r_mean, 0.01) << " " << std::max(s.r_std, 0.01);
      }
      out << "\n";
    }
  }
  const fs::path script = data_dir / (name + "_plot.gp");
  {
    std::ofstream gp(script);
    gp << "set terminal pngcairo noenhanced size 1400,1000 font 'sans,11'\n"
       << "set style data histogram\nset style histogram clustered gap 1\n"
       << "set style fill solid 0.85 border -1\nset boxwidth 0.9\nset logscale y\n"
       << "set grid ytics\nset key outside right top vertical\nset xtics nomirror\n"
       << "set datafile missing '?'\n"
       << "set xrange [-0.6:" << static_cast<double>(groups.size()) - 0.4 << "]\n";
    const char* what[2] = {"mean", "std"};
    const char* title[2] = {"Mean error", "Standard deviation of the error"};
    // A standard deviation needs two cases in some group.
    bool spread = false;
    for (const auto& g : groups)
      for (const auto& m : methods)
        spread = spread || rowsOf(g, m).size() >= 2;
    for (int k = 0; k < (spread ? 2 : 1); ++k) {
      gp << "set output '" << (dir / (name + "_" + what[k] + ".png")).string() << "'\n"
         << "set multiplot layout 2,1 title '" << title[k] << " per group and method (" << name
         << "; log scale)'\n";
      for (int panel = 0; panel < 2; ++panel) {
        gp << "set ylabel '"
           << (panel == 0 ? "(a) translation error (mm)" : "(b) rotation error (deg)")
           << "'\nplot ";
        for (std::size_t m = 0; m < methods.size(); ++m) {
          const std::size_t col =
              2 + 4 * m + 2 * static_cast<std::size_t>(panel) + static_cast<std::size_t>(k);
          gp << (m ? ", " : "") << "'" << data.string() << "' using " << col
             << (m == 0 ? ":xtic(1)" : "") << " title '" << methods[m] << "'";
        }
        gp << "\n";
      }
      gp << "unset multiplot\n";
    }
  }
  const std::string command = "gnuplot '" + script.string() + "' 2>&1";
  if (std::system(command.c_str()) != 0)
    std::fprintf(stderr,
                 "pcl_icf_bench: gnuplot failed (is gnuplot-nox installed?); the "
                 "data and script are in %s\n",
                 data_dir.string().c_str());
}

int usage(const char* program) {
  std::fprintf(stderr,
               "Usage: %s [--out DIR] [--plots DIR] [--name NAME] [--methods A,B]\n"
               "          [--thesis-cases N] [--limit N] [--threads N] [--ia-iterations N]\n"
               "          [--sac K=V,...] [--repeat N] [--no-plots] MANIFEST...\n"
               "Methods: icf-fast icf-thesis icf-fast+sac icf-sac icp-p2p icp-p2plane "
               "sacia+icp prerej+icp\n",
               program);
  return 2;
}

std::vector<std::string> splitComma(const std::string& s) {
  std::vector<std::string> parts;
  std::stringstream in(s);
  std::string part;
  while (std::getline(in, part, ','))
    if (!part.empty())
      parts.push_back(part);
  return parts;
}

void applySacOverride(pcl::icf::SacParams& p, const std::string& kv) {
  const auto eq = kv.find('=');
  if (eq == std::string::npos)
    throw std::invalid_argument("--sac expects KEY=VALUE, got " + kv);
  const std::string key = kv.substr(0, eq);
  const double v = std::stod(kv.substr(eq + 1));
  if (key == "voxel_size")
    p.voxel_size = static_cast<float>(v);
  else if (key == "normal_radius")
    p.normal_radius = static_cast<float>(v);
  else if (key == "feature_radius")
    p.feature_radius = static_cast<float>(v);
  else if (key == "max_iterations")
    p.max_iterations = static_cast<int>(v);
  else if (key == "correspondence_randomness")
    p.correspondence_randomness = static_cast<int>(v);
  else if (key == "similarity_threshold")
    p.similarity_threshold = static_cast<float>(v);
  else if (key == "max_correspondence_distance")
    p.max_correspondence_distance = static_cast<float>(v);
  else if (key == "inlier_fraction")
    p.inlier_fraction = static_cast<float>(v);
  else if (key == "model_samples")
    p.model_samples = static_cast<std::size_t>(v);
  else if (key == "min_sample_distance")
    p.min_sample_distance = static_cast<float>(v);
  else if (key == "seed")
    p.seed = static_cast<std::uint64_t>(v);
  else
    throw std::invalid_argument("--sac: unknown field " + key);
}

}  // namespace

int main(int argc, char** argv) {
  fs::path out_dir = "bench_out", plot_dir;
  std::string name;
  std::vector<std::string> methods = kAllMethods, manifests;
  int thesis_cases = 5, limit = -1, threads = 0, ia_iterations = 1000, repeat = 1;
  bool plots = true;
  pcl::icf::SacParams sac;
  std::string command_line = "pcl_icf_bench";
  for (int i = 1; i < argc; ++i)
    command_line += std::string(" ") + argv[i];
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc)
          throw std::invalid_argument(arg + " needs a value");
        return argv[++i];
      };
      if (arg == "--out")
        out_dir = value();
      else if (arg == "--plots")
        plot_dir = value();
      else if (arg == "--name")
        name = value();
      else if (arg == "--methods") {
        methods = splitComma(value());
        for (const auto& m : methods)
          if (std::find(kAllMethods.begin(), kAllMethods.end(), m) == kAllMethods.end())
            throw std::invalid_argument("unknown method " + m);
      } else if (arg == "--thesis-cases")
        thesis_cases = std::stoi(value());
      else if (arg == "--limit")
        limit = std::stoi(value());
      else if (arg == "--threads")
        threads = std::stoi(value());
      else if (arg == "--ia-iterations")
        ia_iterations = std::stoi(value());
      else if (arg == "--sac") {
        for (const auto& kv : splitComma(value()))
          applySacOverride(sac, kv);
      } else if (arg == "--repeat")
        repeat = std::stoi(value());
      else if (arg == "--no-plots")
        plots = false;
      else if (arg == "-h" || arg == "--help")
        return usage(argv[0]) - 2;
      else if (!arg.empty() && arg[0] == '-')
        throw std::invalid_argument("unknown option " + arg);
      else
        manifests.push_back(arg);
    }
    if (manifests.empty())
      throw std::invalid_argument("no manifest given");
    if (threads < 0)
      throw std::invalid_argument("--threads must be >= 0");
    if (repeat < 1 || repeat > 100)
      throw std::invalid_argument("--repeat must lie in [1, 100]");
    sac.validate();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcl_icf_bench: %s\n", e.what());
    return usage(argv[0]);
  }
  if (plot_dir.empty())
    plot_dir = out_dir;
  if (name.empty())
    name = fs::path(manifests[0]).stem().string();
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);  // PCD field and SAC-IA warnings

  std::vector<CaseSpec> cases;
  try {
    for (const auto& m : manifests) {
      auto more = readManifest(m);
      cases.insert(cases.end(), more.begin(), more.end());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcl_icf_bench: %s\n", e.what());
    return 2;
  }
  std::vector<std::string> groups;
  {
    std::map<std::string, int> seen;
    std::vector<CaseSpec> kept;
    for (const auto& c : cases) {
      if (!seen.count(c.group))
        groups.push_back(c.group);
      if (limit < 0 || seen[c.group] < limit)
        kept.push_back(c);
      ++seen[c.group];
    }
    cases = kept;
  }

  pcl::icf::IcfParams icf_base;
  icf_base.threads = threads;
  icf_base.sac = sac;
  pcl::icf::SacParams prerejective = sac;
  pcl::icf::SacParams ia = sac;
  ia.method = pcl::icf::SacMethod::InitialAlignment;
  ia.max_iterations = ia_iterations;

  const bool tty = isatty(STDERR_FILENO);
  std::map<std::string, std::shared_ptr<PreparedModel>> models;
  std::vector<Row> rows;
  std::map<std::string, int> group_index;
  const auto begin = Clock::now();
  try {
    for (std::size_t ci = 0; ci < cases.size(); ++ci) {
      const CaseSpec& c = cases[ci];
      const std::string model_key = c.model.string() + "@" + std::to_string(c.scale);
      if (!models.count(model_key)) {
        if (tty)
          std::fprintf(stderr, "\r\033[Kpreparing %s ...", c.model.filename().string().c_str());
        models[model_key] = prepareModel(c.model, c.scale, sac, threads);
      }
      PreparedModel& model = *models[model_key];
      Eigen::Vector3f camera;
      const CloudXYZ::Ptr cluster = loadCluster(c, model, camera);
      const t::Symmetry symmetry = parseSymmetry(c.symmetry_spec, c.source);
      const Eigen::Isometry3d& reference = c.reference;
      const int index_in_group = group_index[c.group]++;

      for (const auto& m : methods) {
        if (m == "icf-thesis" && thesis_cases >= 0 && index_in_group >= thesis_cases)
          continue;
        if (tty) {
          const double elapsed = std::chrono::duration<double>(Clock::now() - begin).count();
          std::fprintf(stderr, "\r\033[K[%zu/%zu] %s (%zu points): %s   %.0f s elapsed", ci + 1,
                       cases.size(), c.name.c_str(), cluster->size(), m.c_str(), elapsed);
        }
        auto runOnce = [&]() {
          if (m.rfind("icf-", 0) == 0) {
            pcl::icf::IcfParams p = icf_base;
            p.strategy = m == "icf-thesis" ? pcl::icf::SearchStrategy::Thesis
                                           : pcl::icf::SearchStrategy::Fast;
            p.fallback = m == "icf-fast+sac" ? pcl::icf::FallbackPolicy::Auto
                         : m == "icf-sac"    ? pcl::icf::FallbackPolicy::Always
                                             : pcl::icf::FallbackPolicy::Off;
            return runIcf(cluster, model, p);
          }
          if (m == "icp-p2p" || m == "icp-p2plane")
            return runIcp(cluster, model, m == "icp-p2plane", threads);
          return runSacIcp(cluster, model, m == "sacia+icp" ? ia : prerejective, threads);
        };
        MethodRun run = runOnce();
        // Every method is deterministic: repeats only steady the time (their median).
        std::vector<double> times = {run.ms};
        for (int r = 1; r < repeat && m != "icf-thesis"; ++r) {
          const MethodRun again = runOnce();
          if (!again.object_pose.isApprox(run.object_pose, 1e-5f))
            std::fprintf(stderr, "pcl_icf_bench: %s on %s gave another pose when repeated\n",
                         m.c_str(), c.name.c_str());
          times.push_back(again.ms);
        }
        run.ms = median(times);

        Row row;
        row.case_name = c.name;
        row.group = c.group;
        row.method = m;
        row.points = cluster->size();
        row.ms = run.ms;
        row.converged = run.converged;
        row.detail = run.detail;
        row.object_pose = run.object_pose;
        const Eigen::Isometry3d est(run.object_pose.cast<double>());
        const t::PoseError e = t::poseError(est * reference, c.truth * reference, symmetry);
        const t::PoseError strict =
            t::poseError(est * reference, c.truth * reference, t::Symmetry::none());
        row.t_mm = 1e3 * e.translation;
        row.r_deg = e.rotation_deg;
        row.r_nosym_deg = strict.rotation_deg;
        row.adds_mm = 1e3 * addS(model, est, c.truth);
        row.success = e.translation <= kSuccessTranslation && e.rotation_deg <= kSuccessRotation;
        rows.push_back(row);
      }
    }
  } catch (const std::exception& e) {
    if (tty)
      std::fprintf(stderr, "\n");
    std::fprintf(stderr, "pcl_icf_bench: %s\n", e.what());
    return 2;
  }
  if (tty)
    std::fprintf(stderr, "\r\033[Kdone: %zu cases x %zu methods in %.0f s\n", cases.size(),
                 methods.size(), std::chrono::duration<double>(Clock::now() - begin).count());

  // ---- outputs
  fs::create_directories(out_dir);
  {
    std::ofstream csv(out_dir / (name + "_cases.csv"));
    csv << "case,group,method,points,t_err_mm,r_err_deg,r_err_nosym_deg,adds_mm,time_ms,"
           "success,converged,detail,pose_row_major\n";
    csv.precision(6);
    for (const Row& r : rows) {
      csv << csvEscape(r.case_name) << "," << csvEscape(r.group) << "," << r.method << ","
          << r.points << "," << r.t_mm << "," << r.r_deg << "," << r.r_nosym_deg << "," << r.adds_mm
          << "," << r.ms << "," << r.success << "," << r.converged << "," << csvEscape(r.detail)
          << ",";
      // The estimated pose (model -> scene), the top 3 rows; full precision to recompute.
      csv.precision(9);
      for (int i = 0; i < 12; ++i)
        csv << (i ? " " : "") << r.object_pose(i / 4, i % 4);
      csv.precision(6);
      csv << "\n";
    }
  }
  auto rowsOf = [&rows](const std::string& group, const std::string& method) {
    std::vector<const Row*> selected;
    for (const Row& r : rows)
      if (r.method == method && (group.empty() || r.group == group))
        selected.push_back(&r);
    return selected;
  };
  {
    std::ofstream csv(out_dir / (name + "_summary.csv"));
    csv << "group,method,cases,success_rate,t_mean_mm,t_median_mm,t_std_mm,r_mean_deg,"
           "r_median_deg,r_std_deg,adds_mean_mm,adds_median_mm,time_median_ms\n";
    std::vector<std::string> all_groups = {""};
    all_groups.insert(all_groups.end(), groups.begin(), groups.end());
    for (const auto& g : all_groups)
      for (const auto& m : methods) {
        const auto selected = rowsOf(g, m);
        if (selected.empty())
          continue;
        const Summary s = summarize(selected);
        csv << csvEscape(g.empty() ? "ALL" : g) << "," << m << "," << s.n << "," << s.success << ","
            << s.t_mean << "," << s.t_median << "," << s.t_std << "," << s.r_mean << ","
            << s.r_median << "," << s.r_std << "," << s.adds_mean << "," << s.adds_median << ","
            << s.time_median << "\n";
      }
  }
  std::ostringstream md;
  md << "### " << name << "\n\n`" << command_line << "`\n\n"
     << cases.size() << " cases in " << groups.size()
     << " groups; success = translation <= " << 1e3 * kSuccessTranslation
     << " mm and rotation <= " << kSuccessRotation
     << " deg (symmetry-aware); std = sample standard deviation; times per cluster, model "
        "preparation excluded";
  if (std::find(methods.begin(), methods.end(), "icf-thesis") != methods.end() && thesis_cases >= 0)
    md << "; icf-thesis on the first " << thesis_cases << " cases of each group only";
  if (repeat > 1)
    md << "; each time is the median of " << repeat << " repeats (icf-thesis: one run)";
  md << ".\n\nAll groups:\n\n"
     << formatTable(methods, [&](const std::string& m) { return rowsOf("", m); });
  for (const auto& g : groups)
    md << "\n"
       << g << ":\n\n"
       << formatTable(methods, [&](const std::string& m) { return rowsOf(g, m); });
  md << "\nModel preparation (once per model, not in the times above):\n\n"
        "| model | ICF model (ms) | SAC features (ms) |\n|---|---:|---:|\n";
  for (const auto& [key, model] : models) {
    char line[256];
    std::snprintf(line, sizeof(line), "| %s | %.0f | %.0f |\n",
                  fs::path(key.substr(0, key.rfind('@'))).filename().string().c_str(),
                  model->icf_build_ms, model->sac_build_ms);
    md << line;
  }
  {
    std::ofstream file(out_dir / (name + ".md"));
    file << md.str();
  }
  std::cout << md.str();
  if (plots)
    writePlots(out_dir, plot_dir, name, groups, methods,
               [&](const std::string& g, const std::string& m) { return rowsOf(g, m); });
  return 0;
}
