// pcl_icf_bench: ICF against PCL's registration pipelines on the same clusters. The manifest
// is read in bench_manifest, the methods run in bench_methods, the outputs are written by
// bench_report.
//
//   pcl_icf_bench [options] MANIFEST...
//     --out DIR            CSV and markdown go here (default bench_out)
//     --plots DIR          PNG bar charts go here (default: --out)
//     --name NAME          file prefix (default: the first manifest's stem)
//     --methods A,B,...    subset of the methods below (default: all but icf-scene)
//     --thesis-cases N     run icf-thesis on the first N cases of each group only (default 5;
//                          -1: all). It costs 10-50 s per case.
//     --limit N            at most N cases per group
//     --threads N          threads for ICF and for the feature estimation (0: all cores)
//     --ia-iterations N    SAC-IA hypotheses (default 1000)
//     --sac K=V,...        override SacParams fields for both SAC pipelines and the fallback:
//                          voxel_size, normal_radius, feature_radius, max_iterations,
//                          correspondence_randomness, similarity_threshold,
//                          max_correspondence_distance, inlier_fraction, model_samples, seed
//     --icf K=V,...        override registered IcfParams fields (pcl_icf_tool --list-fields
//                          lists them with their ranges and defaults) for the icf-* methods and
//                          icf-scene, for calibration curves: rotations, keep, subsample,
//                          prescreen_points, prescreen_share, exact_candidates,
//                          candidate_points, coarse_points, fine_iterations, max_points, ...
//     --verification K=V,..., --tuning K=V,...  override icf-scene's registered
//                          LocalizerParams fields (the same names as Python's keywords and the
//                          tool's --set): fit_residual, max_residual, full_evidence,
//                          max_conflict, max_continuation; clusters, point_pairs, per_cluster,
//                          judged, per_location, min_prescore, hypothesis_crop_margin,
//                          refine_points, final_points, pp_kept, pp_per_place, pp_references,
//                          pp_reference_share, pp_rescored, pp_peaks, pp_spread, ...; --tuning
//                          also takes the models' point pair table: pp_step, pp_coplanar, pp_cap
//                          and the camera's: depth_systematic=0 for the simulated scenes of
//                          pcl_icf_make_dataset (no low-frequency depth error)
//     --repeat N           run every method N times per case and report the median time
//                          (the poses are identical: every method is seeded); icf-thesis
//                          runs once. For small suites on a busy machine.
//     --no-plots           skip gnuplot
//     --ppf-sampling S     ppf+icp's model sampling relative to the model's diameter
//                          (default 0.06; OpenCV's sample: 0.025, minutes per primitive)
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
//   o3d-ransac+icp, o3d-fgr+icp, ppf+icp   Open3D's and OpenCV's registration, when compiled
//                 in (PCL_ICF_BENCH_PEERS; bench_peers.h says what runs)
//   icf-scene     pcl::icf::localization::localizeObject on the WHOLE scene (segmentation,
//                 every cluster, acceptance, ranking), ignoring cluster=; its time is the
//                 whole call. Only when named in --methods.
//   icf-objects   pcl::icf::localization::localizeObjects on the whole scene with the case's
//                 model and every other model of the manifests in one call (their instances
//                 compete for the scene's points); scored on the case's model, the others'
//                 poses unscored (the manifest has no truth for them). Only when named.
//
// A case with truth=none has the model absent from its scene: a method that claims a pose there
// (its own verdict, the CSV's converged) gives a false pose. The cluster methods are not run on
// such a case when its cluster is the whole file (cluster=all): they need a cluster.
//
// Per method: success rate (translation <= 1 cm and rotation <= 5 degrees, symmetry-aware) and
// false-pose rate (over the target-absent cases),
// mean / median / standard deviation of the translation error (mm) and rotation error
// (degrees) as the thesis's chapter 7 reports them, ADD-S (mm: mean distance from 2000 truly posed
// surface samples to the estimated model surface) and the median time. Writes NAME_cases.csv (one
// row per case and method), NAME_summary.csv, NAME.md (also printed on stdout), the plot's data and
// gnuplot script (NAME_plot.dat/.gp) in
// --out and, with gnuplot, NAME_mean.png and NAME_std.png in --plots (bar charts per group and
// method like the thesis's figures 7.5 and 7.6). Progress goes to stderr
// when it is a terminal. Exit codes: 0 done, 2 bad usage, manifest or data.
#include "bench_bop.h"
#include "bench_manifest.h"
#include "bench_methods.h"
#ifdef PCL_ICF_HAVE_PEERS
#include "bench_peers.h"
#endif
#include "bench_report.h"
#include "bench_scene.h"
#include "common/arguments.h"

#include <pcl/icf/localization/localizer_fields.h>
#include <pcl/icf/registration/parameter_fields.h>

#include <pcl/console/print.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;
namespace t = pcl::icf::synthetic;
using namespace pcl_icf_tools::bench;
using Clock = std::chrono::steady_clock;

/** The names of the methods run on the case's cluster (clusterMethodTable), the default set. */
const std::vector<std::string>& clusterMethods();

bool isPeer(const std::string& m) {
#ifdef PCL_ICF_HAVE_PEERS
  return std::find(peerMethods().begin(), peerMethods().end(), m) != peerMethods().end();
#else
  (void)m;
  return false;
#endif
}
/** The methods run on the whole scene (bench_scene.h): one model, every model in one call. */
const std::string kSceneMethod = "icf-scene";
const std::string kObjectsMethod = "icf-objects";

bool isSceneMethod(const std::string& m) {
  return m == kSceneMethod || m == kObjectsMethod;
}

struct Options {
  fs::path out_dir = "bench_out", plot_dir;
  std::string name;
  std::vector<std::string> methods = clusterMethods(), manifests;
  int thesis_cases = 5, limit = -1, threads = 0, ia_iterations = 1000, repeat = 1;
  /** ppf+icp's model sampling step relative to the model's diameter (PPF3DDetector's
   * relativeSamplingStep). OpenCV's sample uses 0.025, but its training walks hash chains that
   * grow with the many equal pair features of flat and round faces: on the thesis's models 0.05
   * took over 11 minutes for one model, 0.06 takes 8-53 s, 0.08 0.5-4 s. */
  double ppf_sampling = 0.06;
  bool plots = true;
  /** icf-scene's acceptance threshold (the localizer's default when unset); 0 makes every case
   * report its best hypothesis with its confidence, for calibration curves. */
  std::optional<double> scene_min_confidence;
  pcl::icf::SacParams sac;
  /** --icf's and --verification's fields in order, applied on top of the defaults (icfParams,
   * sceneParams); --verification's are icf-scene's. */
  std::vector<std::pair<std::string, double>> icf_fields, verification_fields, tuning_fields;
  /** The models' preparation: --tuning's pp_step and pp_coplanar. */
  pcl::icf::IcfModelParams model_params;
  std::string command_line = "pcl_icf_bench";
};

int usage(const char* program) {
  std::fprintf(stderr,
               "Usage: %s [--out DIR] [--plots DIR] [--name NAME] [--methods A,B]\n"
               "          [--thesis-cases N] [--limit N] [--threads N] [--ia-iterations N]\n"
               "          [--sac K=V,...] [--icf K=V,...] [--verification K=V,...]\n"
               "          [--tuning K=V,...] [--repeat N] [--no-plots]\n"
               "          [--scene-min-confidence C] [--ppf-sampling S] MANIFEST...\n"
               "       %s --bop ROOT [--split S] [--targets FILE] [--out DIR] [--threads N]\n"
               "          [--models DIR] [--seed S] [--vsd-delta MM] [--shard K/N | --merge]\n"
               "          [--selection icf|ghv]\n"
               "Methods (default: all but icf-scene):",
               program, program);
  for (const auto& m : clusterMethods())
    std::fprintf(stderr, " %s", m.c_str());
  std::fprintf(stderr,
               ", icf-scene (whole scene), icf-objects (whole scene, every model of the "
               "manifests in one call)\n");
  return 2;
}

/** KEY and VALUE of \a option's KEY=VALUE \a kv. */
std::pair<std::string, double> keyValue(const std::string& option, const std::string& kv) {
  const auto eq = kv.find('=');
  if (eq == std::string::npos)
    throw std::invalid_argument(option + " expects KEY=VALUE, got " + kv);
  const std::string key = kv.substr(0, eq);
  return {key, pcl_icf_tools::parseNumber(option + " " + key, kv.substr(eq + 1))};
}

void applySacOverride(pcl::icf::SacParams& p, const std::string& kv) {
  const auto [key, v] = keyValue("--sac", kv);
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

/** Sets \a p's registered field \a key (parameter_fields.h) to \a v; std::invalid_argument
 * for another name or a value of the wrong kind. --icf's names are icfFields()'s,
 * --verification's and --tuning's (and --icf's for icf-scene) localizerFields()'s. */
template <typename Params>
void applyOverride(const pcl::icf::FieldRegistry<Params>& registry, Params& p,
                   const std::string& option, const std::string& key, double v) {
  try {
    pcl::icf::setFieldNumber(pcl::icf::findField(registry, key), p, v);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(option + " " + e.what());
  }
}

/** \a o's --icf fields, threads and SacParams applied to \a p. */
void applyIcfOptions(const Options& o, pcl::icf::IcfParams& p) {
  for (const auto& [key, value] : o.icf_fields)
    applyOverride(pcl::icf::icfFields(), p, "--icf", key, value);
  p.threads = o.threads;
  p.tuning().sac = o.sac;
}

/** \a o's ICF parameters: IcfParams' defaults with its --icf fields, threads and SacParams. */
pcl::icf::IcfParams icfParams(const Options& o) {
  pcl::icf::IcfParams p;
  applyIcfOptions(o, p);
  return p;
}

pcl::icf::localization::LocalizerParams sceneParams(const Options& o);

/** The options; std::invalid_argument on a bad one. False for --help. */
bool parseOptions(int argc, char** argv, Options& o) {
  using namespace pcl_icf_tools;
  for (int i = 1; i < argc; ++i)
    o.command_line += std::string(" ") + argv[i];
  // The whole-number options (their ranges are checked after the loop).
  const std::map<std::string, int*> integers = {{"--thesis-cases", &o.thesis_cases},
                                                {"--limit", &o.limit},
                                                {"--threads", &o.threads},
                                                {"--ia-iterations", &o.ia_iterations},
                                                {"--repeat", &o.repeat}};
  const std::map<std::string, fs::path*> folders = {{"--out", &o.out_dir},
                                                    {"--plots", &o.plot_dir}};
  ArgumentReader args(argc, argv);
  while (!args.done()) {
    const std::string arg = args.next();
    if (const auto integer = integers.find(arg); integer != integers.end())
      *integer->second = static_cast<int>(parseInteger(
          arg, args.value(arg), std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
    else if (const auto folder = folders.find(arg); folder != folders.end())
      *folder->second = args.value(arg);
    else if (arg == "--name")
      o.name = args.value(arg);
    else if (arg == "--methods") {
      o.methods = splitComma(args.value(arg));
      for (const auto& m : o.methods)
        if (!isSceneMethod(m) && std::find(clusterMethods().begin(), clusterMethods().end(), m) ==
                                     clusterMethods().end())
          throw std::invalid_argument("unknown method " + m);
    } else if (arg == "--sac") {
      for (const auto& kv : splitComma(args.value(arg)))
        applySacOverride(o.sac, kv);
    } else if (arg == "--icf") {
      for (const auto& kv : splitComma(args.value(arg))) {
        o.icf_fields.push_back(keyValue(arg, kv));
      }
    } else if (arg == "--verification") {
      for (const auto& kv : splitComma(args.value(arg))) {
        o.verification_fields.push_back(keyValue(arg, kv));
      }
    } else if (arg == "--tuning") {
      for (const auto& kv : splitComma(args.value(arg))) {
        const auto [key, value] = keyValue(arg, kv);
        // The point pair table's sampling is the model's preparation, not the localizer's.
        if (key == "pp_step")
          o.model_params.point_pairs.sampling_step = static_cast<float>(value);
        else if (key == "pp_coplanar")
          o.model_params.point_pairs.coplanar_deg = static_cast<float>(value);
        else if (key == "pp_cap")
          o.model_params.point_pairs.max_bin_pairs = static_cast<std::size_t>(value);
        else
          o.tuning_fields.emplace_back(key, value);
      }
      o.model_params.point_pairs.validate();
    } else if (arg == "--exact-mesh")
      throw UsageError(
          "--exact-mesh is gone: one rule verifies every mesh; for the simulated scenes of "
          "pcl_icf_make_dataset give --tuning depth_systematic=0");
    else if (arg == "--ppf-sampling")
      o.ppf_sampling = parseNumber(arg, args.value(arg));
    else if (arg == "--scene-min-confidence")
      o.scene_min_confidence = parseNumber(arg, args.value(arg));
    else if (arg == "--no-plots") {
      args.noValue(arg);
      o.plots = false;
    } else if (arg == "-h" || arg == "--help")
      return false;
    else if (isOption(arg))
      throw UsageError("unknown option " + arg);
    else
      o.manifests.push_back(arg);
  }
  if (o.manifests.empty())
    throw std::invalid_argument("no manifest given");
  if (o.threads < 0)
    throw std::invalid_argument("--threads must be >= 0");
  if (o.repeat < 1 || o.repeat > 100)
    throw std::invalid_argument("--repeat must lie in [1, 100]");
  if (!(o.ppf_sampling >= 0.01 && o.ppf_sampling <= 0.5))
    throw std::invalid_argument("--ppf-sampling must lie in [0.01, 0.5]");
  o.sac.validate();
  icfParams(o).validate();  // the --icf fields' names and ranges, before any case runs
  const bool scene_method = std::any_of(o.methods.begin(), o.methods.end(), isSceneMethod);
  if ((!o.verification_fields.empty() || !o.tuning_fields.empty()) && !scene_method)
    throw std::invalid_argument(
        "--verification and --tuning are for icf-scene and icf-objects: add one to --methods");
  sceneParams(o).validate();  // --verification's and --tuning's fields
  if (o.plot_dir.empty())
    o.plot_dir = o.out_dir;
  if (o.name.empty())
    o.name = fs::path(o.manifests[0]).stem().string();
  return true;
}

/** Every manifest's cases, at most \a limit per group (all for -1); \a groups in order of
 * first appearance. */
std::vector<CaseSpec> readCases(const Options& o, std::vector<std::string>& groups) {
  std::vector<CaseSpec> cases;
  std::map<std::string, int> seen;
  for (const auto& m : o.manifests)
    for (const auto& c : readManifest(m)) {
      if (!seen.count(c.group))
        groups.push_back(c.group);
      if (o.limit < 0 || seen[c.group] < o.limit)
        cases.push_back(c);
      ++seen[c.group];
    }
  return cases;
}

/** What a case's methods run on: the cluster (cluster methods), the whole scene (icf-scene);
 * each loaded only when a selected method needs it. */
struct CaseInput {
  CloudXYZ::Ptr cluster;
  SceneInput scene;
  std::vector<const PreparedModel*> other_models;  ///< icf-objects: the manifests' other models
};

/** icf-scene's parameters: the localizer's defaults with the
 * bench's threads, SAC, --icf and --verification fields on top. */
pcl::icf::localization::LocalizerParams sceneParams(const Options& o) {
  pcl::icf::localization::LocalizerParams p;
  p.threads = o.threads;
  p.tuning().icf.tuning().sac = o.sac;
  const auto& fields = pcl::icf::localization::localizerFields();
  for (const auto& [key, value] : o.icf_fields)
    applyOverride(fields, p, "--icf", key, value);
  for (const auto& [key, value] : o.verification_fields)
    applyOverride(fields, p, "--verification", key, value);
  for (const auto& [key, value] : o.tuning_fields)
    applyOverride(fields, p, "--tuning", key, value);
  if (o.scene_min_confidence)
    p.min_confidence = *o.scene_min_confidence;
  return p;
}

/** A method run on the case's cluster: its name and how it runs. */
struct ClusterMethod {
  std::string name;
  std::function<MethodRun(const CloudXYZ::Ptr& cluster, const PreparedModel& model,
                          const Options& o)>
      run;
};

/** The methods run on the case's cluster, in the default order: ICF's (search strategy and
 * SampleConsensus fallback), PCL's ICP and sample consensus pipelines and, when compiled in
 * (PCL_ICF_BENCH_PEERS), Open3D's and OpenCV's (bench_peers.h). */
const std::vector<ClusterMethod>& clusterMethodTable() {
  static const std::vector<ClusterMethod> table = [] {
    using pcl::icf::FallbackPolicy;
    using pcl::icf::SearchStrategy;
    const auto icf = [](SearchStrategy strategy, FallbackPolicy fallback) {
      return [=](const CloudXYZ::Ptr& cluster, const PreparedModel& model, const Options& o) {
        pcl::icf::IcfParams p = icfParams(o);
        p.strategy = strategy;
        p.fallback = fallback;
        return runIcf(cluster, model, p);
      };
    };
    const auto icp = [](bool plane) {
      return [=](const CloudXYZ::Ptr& cluster, const PreparedModel& model, const Options& o) {
        return runIcp(cluster, model, plane, o.threads);
      };
    };
    std::vector<ClusterMethod> t = {
        {"icf-fast", icf(SearchStrategy::Fast, FallbackPolicy::Off)},
        {"icf-thesis", icf(SearchStrategy::Thesis, FallbackPolicy::Off)},
        {"icf-fast+sac", icf(SearchStrategy::Fast, FallbackPolicy::Auto)},
        {"icf-sac", icf(SearchStrategy::Fast, FallbackPolicy::Always)},
        {"icp-p2p", icp(false)},
        {"icp-p2plane", icp(true)},
        {"sacia+icp",
         [](const CloudXYZ::Ptr& cluster, const PreparedModel& model, const Options& o) {
           pcl::icf::SacParams sac = o.sac;
           sac.method = pcl::icf::SacMethod::InitialAlignment;
           sac.max_iterations = o.ia_iterations;
           return runSacIcp(cluster, model, sac, o.threads);
         }},
        {"prerej+icp",
         [](const CloudXYZ::Ptr& cluster, const PreparedModel& model, const Options& o) {
           return runSacIcp(cluster, model, o.sac, o.threads);
         }},
    };
#ifdef PCL_ICF_HAVE_PEERS
    for (const std::string& name : peerMethods())
      t.push_back({name, [name](const CloudXYZ::Ptr& cluster, const PreparedModel& model,
                                const Options& o) {
                     return runPeer(name, cluster, model, o.sac.voxel_size,
                                    static_cast<int>(o.sac.seed), o.threads);
                   }});
#endif
    return t;
  }();
  return table;
}

const std::vector<std::string>& clusterMethods() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const ClusterMethod& m : clusterMethodTable())
      n.push_back(m.name);
    return n;
  }();
  return names;
}

/** Runs one method on one case: the localizer on the whole scene, or a cluster method of
 * clusterMethodTable on the case's cluster. */
MethodRun runMethod(const std::string& m, const CaseInput& in, const PreparedModel& model,
                    const Options& o) {
  if (m == kSceneMethod)
    return runScene(in.scene, model, sceneParams(o));
  if (m == kObjectsMethod)
    return runSceneWithOthers(in.scene, model, in.other_models, sceneParams(o));
  for (const ClusterMethod& method : clusterMethodTable())
    if (method.name == m)
      return method.run(in.cluster, model, o);
  throw std::logic_error("runMethod: unknown method " + m);
}

/** The method's run, repeated o.repeat times (icf-thesis once) for its median time; every
 * method is seeded, so repeats only steady the time (a differing pose is reported). */
MethodRun runRepeated(const std::string& m, const CaseSpec& c, const CaseInput& in,
                      const PreparedModel& model, const Options& o) {
  MethodRun run = runMethod(m, in, model, o);
  std::vector<double> times = {run.ms};
  for (int r = 1; r < o.repeat && m != "icf-thesis"; ++r) {
    const MethodRun again = runMethod(m, in, model, o);
    if (!again.object_pose.isApprox(run.object_pose, 1e-5f))
      std::fprintf(stderr, "pcl_icf_bench: %s on %s gave another pose when repeated\n", m.c_str(),
                   c.name.c_str());
    times.push_back(again.ms);
  }
  run.ms = median(times);
  return run;
}

/** The run measured against the case's truth (symmetry-aware, in the case's reference
 * frame); on a target-absent case only whether it claimed a pose. */
Row measure(const std::string& m, const CaseSpec& c, std::size_t points, const MethodRun& run,
            const PreparedModel& model) {
  Row row;
  row.case_name = c.name;
  row.group = c.group;
  row.method = m;
  row.points = points;
  row.ms = run.ms;
  row.converged = run.converged;
  row.detail = run.detail;
  row.confidence = run.confidence;
  row.verification = run.verification;
  row.object_pose = run.object_pose;
  if (c.absent) {
    row.absent = true;
    row.false_pose = run.converged;
    return row;
  }
  const t::Symmetry symmetry = parseSymmetry(c.symmetry_spec, c.source);
  const Eigen::Isometry3d est(run.object_pose.cast<double>());
  // The translation error at the bounding box's centre unless the manifest names another.
  Eigen::Isometry3d reference = c.reference;
  if (!c.center_set)
    reference.translation() = model.box_centre;
  const t::PoseError e = t::poseError(est * reference, c.truth * reference, symmetry);
  const t::PoseError strict =
      t::poseError(est * reference, c.truth * reference, t::Symmetry::none());
  row.t_mm = 1e3 * e.translation;
  row.r_deg = e.rotation_deg;
  row.r_nosym_deg = strict.rotation_deg;
  row.adds_mm = 1e3 * addS(model, est, c.truth);
  const auto right = [&](const t::PoseError& error, double adds) {
    return error.translation <= kSuccessTranslation && adds < kSuccessAddS * model.diameter;
  };
  row.success = right(e, 1e-3 * row.adds_mm);
  row.strict_success = row.success && e.rotation_deg <= kSuccessRotation;
  // icf-scene: is the truth among the poses it reported as as good (ambiguity, doc/localizer.md)?
  row.success_among_alternatives = row.success;
  for (const Eigen::Matrix4f& alt : run.alternative_poses) {
    const Eigen::Isometry3d alt_pose(alt.cast<double>());
    const t::PoseError a = t::poseError(alt_pose * reference, c.truth * reference, symmetry);
    row.success_among_alternatives =
        row.success_among_alternatives || right(a, addS(model, alt_pose, c.truth));
  }
  return row;
}

using ModelCache = std::map<std::string, std::shared_ptr<PreparedModel>>;

/** A target-absent case whose cluster is its whole file: there is no cluster to give the
 * cluster methods (a whole frame, table included, is not one). */
bool withoutCluster(const CaseSpec& c) {
  return c.absent && c.cluster == "all";
}

bool runsOnCluster(const std::string& m) {
  return !isSceneMethod(m);
}

/** Whether method \a m runs on case \a c, the case's \a index_in_group-th. */
bool runs(const std::string& m, const CaseSpec& c, int index_in_group, const Options& o) {
  if (m == "icf-thesis" && o.thesis_cases >= 0 && index_in_group >= o.thesis_cases)
    return false;
  return !runsOnCluster(m) || !withoutCluster(c);
}

/** The case's cluster and scene, each when a selected method needs it (not timed). */
CaseInput loadInput(const CaseSpec& c, const PreparedModel& model, const Options& o) {
  CaseInput in;
  Eigen::Vector3f camera;
  for (const auto& m : o.methods) {
    if (!runsOnCluster(m) && !in.scene.rgba && !in.scene.xyz)
      in.scene = loadScene(c);
    if (runsOnCluster(m) && !in.cluster && !withoutCluster(c))
      in.cluster = loadCluster(c, model, camera);
  }
  return in;
}

std::string modelKey(const CaseSpec& c) {
  return c.model.string() + "@" + std::to_string(c.scale);
}

const PreparedModel& modelOf(const CaseSpec& c, const Options& o, ModelCache& models, bool tty) {
  const std::string model_key = modelKey(c);
  if (!models.count(model_key)) {
    if (tty)
      std::fprintf(stderr, "\r\033[Kpreparing %s ...", c.model.filename().string().c_str());
    auto model = prepareModel(c.model, c.scale, o.sac, o.threads, o.model_params);
#ifdef PCL_ICF_HAVE_PEERS
    if (std::any_of(o.methods.begin(), o.methods.end(), isPeer))
      model->peers = preparePeerModel(*model, o.sac.voxel_size, o.ppf_sampling, o.threads,
                                      model->peer_build_ms);
#endif
    models[model_key] = model;
  }
  return *models[model_key];
}

/** icf-objects' other models for case \a c: every model of \a cases but \a c's, once each, in
 * order of first appearance (prepared when first needed). */
std::vector<const PreparedModel*> otherModels(const CaseSpec& c, const std::vector<CaseSpec>& cases,
                                              const Options& o, ModelCache& models, bool tty) {
  std::vector<const PreparedModel*> others;
  std::vector<std::string> keys = {modelKey(c)};
  for (const CaseSpec& other : cases)
    if (std::find(keys.begin(), keys.end(), modelKey(other)) == keys.end()) {
      keys.push_back(modelKey(other));
      others.push_back(&modelOf(other, o, models, tty));
    }
  return others;
}

/** Every selected method on every case, with progress on a terminal; \a skipped counts the
 * cases the cluster methods were not run on (withoutCluster). */
std::vector<Row> runAll(const std::vector<CaseSpec>& cases, const Options& o, ModelCache& models,
                        std::size_t& skipped) {
  const bool tty = isatty(STDERR_FILENO);
  const bool cluster_methods = std::any_of(o.methods.begin(), o.methods.end(),
                                           [](const auto& m) { return runsOnCluster(m); });
  std::vector<Row> rows;
  std::map<std::string, int> group_index;
  const auto begin = Clock::now();
  skipped = 0;
  for (std::size_t ci = 0; ci < cases.size(); ++ci) {
    const CaseSpec& c = cases[ci];
    const PreparedModel& model = modelOf(c, o, models, tty);
    CaseInput in = loadInput(c, model, o);
    if (std::find(o.methods.begin(), o.methods.end(), kObjectsMethod) != o.methods.end())
      in.other_models = otherModels(c, cases, o, models, tty);
    skipped += cluster_methods && withoutCluster(c);
    const int index_in_group = group_index[c.group]++;
    for (const auto& m : o.methods) {
      if (!runs(m, c, index_in_group, o))
        continue;
      const std::size_t points = runsOnCluster(m) ? in.cluster->size() : in.scene.finite_points;
      if (tty) {
        const double elapsed = std::chrono::duration<double>(Clock::now() - begin).count();
        std::fprintf(stderr, "\r\033[K[%zu/%zu] %s (%zu points): %s   %.0f s elapsed", ci + 1,
                     cases.size(), c.name.c_str(), points, m.c_str(), elapsed);
      }
      rows.push_back(measure(m, c, points, runRepeated(m, c, in, model, o), model));
    }
  }
  if (tty)
    std::fprintf(stderr, "\r\033[Kdone: %zu cases x %zu methods in %.0f s\n", cases.size(),
                 o.methods.size(), std::chrono::duration<double>(Clock::now() - begin).count());
  return rows;
}

/** NAME.md: how it ran, the table over all groups, one per group, model preparation times. */
std::string markdownReport(const Options& o, std::size_t case_count, std::size_t skipped,
                           const std::vector<std::string>& groups, const RowSelector& rowsOf,
                           const ModelCache& models) {
  std::ostringstream md;
  md << "### " << o.name << "\n\n`" << o.command_line << "`\n\n"
     << case_count << " cases in " << groups.size()
     << " groups; success = the model's centre within " << 1e3 * kSuccessTranslation
     << " mm and ADD-S below " << 100 * kSuccessAddS
     << "% of its diameter, over the cases with the target present; absent = target-absent "
        "cases (truth=none), false poses = those on which the method claimed a pose; std = "
        "sample standard deviation; times per cluster (icf-scene: per whole scene, segmentation "
        "included), model preparation excluded";
  if (std::find(o.methods.begin(), o.methods.end(), "icf-thesis") != o.methods.end() &&
      o.thesis_cases >= 0)
    md << "; icf-thesis on the first " << o.thesis_cases << " cases of each group only";
  if (o.repeat > 1)
    md << "; each time is the median of " << o.repeat << " repeats (icf-thesis: one run)";
  if (skipped)
    md << "; the cluster methods were not run on the " << skipped
       << " target-absent cases whose cluster is the whole file (cluster=all)";
  md << ".\n\nAll groups:\n\n"
     << formatTable(o.methods, [&](const std::string& m) { return rowsOf("", m); });
  for (const auto& g : groups)
    md << "\n"
       << g << ":\n\n"
       << formatTable(o.methods, [&](const std::string& m) { return rowsOf(g, m); });
  const bool peers = std::any_of(o.methods.begin(), o.methods.end(), isPeer);
  md << "\nModel preparation (once per model, not in the times above):\n\n"
        "| model | ICF model (ms) | SAC features (ms) |"
     << (peers ? " Open3D FPFH (ms) | OpenCV PPF training (ms) |\n|---|---:|---:|---:|---:|\n"
               : "\n|---|---:|---:|\n");
  for (const auto& [key, model] : models) {
    char line[256];
    std::snprintf(line, sizeof(line), "| %s | %.0f | %.0f |",
                  fs::path(key.substr(0, key.rfind('@'))).filename().string().c_str(),
                  model->icf_build_ms, model->sac_build_ms);
    md << line;
    for (const double ms : model->peer_build_ms) {
      std::snprintf(line, sizeof(line), " %.0f |", ms);
      md << line;
    }
    md << "\n";
  }
  return md.str();
}

/** The groups with a target-present row: the error plots' groups. */
std::vector<std::string> groupsWithErrors(const std::vector<std::string>& groups,
                                          const std::vector<Row>& rows) {
  std::vector<std::string> out;
  for (const auto& g : groups)
    if (std::any_of(rows.begin(), rows.end(),
                    [&g](const Row& r) { return r.group == g && !r.absent; }))
      out.push_back(g);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  for (int a = 1; a < argc; ++a)
    if (std::string(argv[a]) == "--bop") {
      pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
      return pcl_icf_bench::runBop(argc, argv);
    }
  Options o;
  try {
    if (!parseOptions(argc, argv, o))
      return usage(argv[0]) - 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcl_icf_bench: %s\n", e.what());
    return usage(argv[0]);
  }
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);  // PCD field and SAC-IA warnings

  std::vector<std::string> groups;
  std::vector<CaseSpec> cases;
  ModelCache models;
  std::vector<Row> rows;
  std::size_t skipped = 0;
  try {
    cases = readCases(o, groups);
    rows = runAll(cases, o, models, skipped);
  } catch (const std::exception& e) {
    if (isatty(STDERR_FILENO))
      std::fputs("\n", stderr);  // below the progress line
    std::fprintf(stderr, "pcl_icf_bench: %s\n", e.what());
    return 2;
  }

  const RowSelector rowsOf = [&rows](const std::string& group, const std::string& method) {
    std::vector<const Row*> selected;
    for (const Row& r : rows)
      if (r.method == method && (group.empty() || r.group == group))
        selected.push_back(&r);
    return selected;
  };
  fs::create_directories(o.out_dir);
  writeCasesCsv(o.out_dir / (o.name + "_cases.csv"), rows);
  writeSummaryCsv(o.out_dir / (o.name + "_summary.csv"), groups, o.methods, rowsOf);
  const std::string md = markdownReport(o, cases.size(), skipped, groups, rowsOf, models);
  std::ofstream(o.out_dir / (o.name + ".md")) << md;
  std::cout << md;
  if (skipped)
    std::fprintf(stderr,
                 "pcl_icf_bench: the cluster methods were not run on %zu target-absent cases "
                 "with cluster=all (use --methods icf-scene for them)\n",
                 skipped);
  const std::vector<std::string> plotted = groupsWithErrors(groups, rows);
  if (o.plots && !plotted.empty())
    writePlots(o.out_dir, o.plot_dir, o.name, plotted, o.methods, rowsOf);
  return 0;
}
