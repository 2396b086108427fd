/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_bench --bop (bench_bop.h): the dataset read by bop_bench_data.h, the poses by
// localizeObjects, the CSV and the shards by bop_results.h, the scores by bop_scores.h.
#include "bench_bop.h"

#include "bop_bench_data.h"
#include "bop_results.h"
#include "bop_scores.h"
#include "common/arguments.h"
#include "ghv_selection.h"

#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/localization/objects_localizer.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace pcl_icf_bench {

namespace {

namespace fs = std::filesystem;
using pcl_icf_tools::ArgumentReader;
using pcl_icf_tools::UsageError;

struct BopOptions {
  fs::path root;
  std::string split = "test";
  fs::path targets;               ///< default ROOT/test_targets_bop19.json
  std::string models = "models";  ///< the models' folder under ROOT (T-LESS: models_cad)
  fs::path out_dir = "out/bop";
  int threads = 0;
  unsigned seed = 1;
  BopShard shard;      ///< --shard, or the environment's (Open MPI, Slurm)
  bool merge = false;  ///< --merge: join the shards in out_dir and score them
  /** --selection: which hypotheses are the frame's objects: localizeObjects's own selection
   * ("icf"), or PCL's Global Hypotheses Verification over the same hypotheses ("ghv"). */
  std::string selection = "icf";
  BopScoreParams scores;
};

BopOptions parseBopOptions(int argc, char** argv) {
  BopOptions o;
  bool vsd_delta_given = false;
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
    else if (a == "--models")
      o.models = args.value(a);
    else if (a == "--vsd-delta") {
      o.scores.vsd_delta_mm = pcl_icf_tools::parsePositive(a, args.value(a));
      vsd_delta_given = true;
    } else if (a == "--shard")
      o.shard = parseShard(args.value(a));
    else if (a == "--merge")
      o.merge = true;
    else if (a == "--selection") {
      o.selection = args.value(a);
      if (o.selection != "icf" && o.selection != "ghv")
        throw UsageError("--selection: icf or ghv, not '" + o.selection + "'");
    } else
      throw UsageError("--bop: unknown option " + a);
  }
  if (o.root.empty())
    throw UsageError("--bop ROOT: the dataset's folder");
  if (o.merge && o.shard.given)
    throw UsageError("--merge joins the shards of a run: give it without --shard");
  if (!o.merge && !o.shard.given)
    o.shard = shardFromEnvironment();
  if (o.targets.empty())
    o.targets = o.root / "test_targets_bop19.json";
  // BOP 2019's delta: 5 mm for ITODD's industrial sensor, 15 mm for every other dataset.
  const std::string folder = o.root.lexically_normal().string();
  if (!vsd_delta_given && folder.find("itodd") != std::string::npos)
    o.scores.vsd_delta_mm = 5.0;
  return o;
}

/** The poses of the shard's images, through the many-objects call. */
std::vector<BopEstimate> localizeImages(BopBenchData& data, const BopOptions& o) {
  pcl::icf::localization::LocalizerParams params;
  params.threads = o.threads;
  params.seed = o.seed;
  std::vector<BopEstimate> rows;
  std::size_t index = 0, done = 0;
  const std::size_t mine = (data.targets().size() + static_cast<std::size_t>(o.shard.count) -
                            static_cast<std::size_t>(o.shard.index)) /
                           static_cast<std::size_t>(o.shard.count);
  for (const auto& [image, targets] : data.targets()) {
    if (!o.shard.has(index++))
      continue;
    const auto cloud = data.cloud(image);
    std::vector<pcl::icf::localization::ObjectQuery> queries;
    for (const auto& t : targets)
      queries.push_back(
          {data.objects().at(t.obj_id).model, "obj_" + std::to_string(t.obj_id), t.inst_count});
    const auto start = std::chrono::steady_clock::now();
    const auto found = pcl::icf::localization::localizeObjects(*cloud, queries, params);
    std::vector<std::vector<int>> kept;
    if (o.selection == "ghv")
      kept = ghvSelect(*cloud, found, queries);
    else
      for (const auto& object : found.objects)
        kept.push_back(object.instances);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (std::size_t k = 0; k < targets.size(); ++k)
      for (const int h : kept[k]) {
        const auto& c = found.objects[k].clusters[static_cast<std::size_t>(h)];
        BopEstimate e;
        e.scene_id = image.first;
        e.im_id = image.second;
        e.obj_id = targets[k].obj_id;
        e.score = c.verification.confidence;
        e.pose.matrix() = c.icf.object_pose.cast<double>();
        e.pose.translation() *= 1000.0;  // metres -> BOP's millimetres
        e.seconds = seconds;
        rows.push_back(e);
      }
    std::fprintf(stderr, "\r%zu/%zu images", ++done, mine);
  }
  std::fputs("\n", stderr);
  sortEstimates(rows);
  return rows;
}

/** Scores \a rows, then writes them to \a csv and the scores to stdout and OUT/bop_scores.md
 * (scored first, so a dataset that fails to score leaves no CSV behind). A split without its
 * ground truth (BOP withholds some) gets its CSV and no scores. */
void scoreAndWrite(BopBenchData& data, const BopOptions& o, const std::vector<BopEstimate>& rows,
                   const fs::path& csv) {
  for (const auto& [image, targets] : data.targets())
    if (!data.truth(image).annotated) {
      writeBopCsv(csv, rows);
      std::printf("%s written (%zu estimates); not scored: scene %d has no scene_gt.json\n",
                  csv.string().c_str(), rows.size(), image.first);
      return;
    }
  std::ostringstream md;
  md << "BOP scores of " << o.root.string() << " (" << o.split << ", " << data.targets().size()
     << " images, " << rows.size() << " estimates; " << csv.string() << ")\n\n"
     << bopScoresTable(data, rows, o.scores);
  writeBopCsv(csv, rows);
  std::ofstream(o.out_dir / "bop_scores.md") << md.str();
  std::fputs(md.str().c_str(), stdout);
}

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
    BopBenchData data(o.root, o.split, o.targets, o.models);
    fs::create_directories(o.out_dir);
    // BOP's name: METHOD_DATASET-SPLIT.csv.
    const std::string method = o.selection == "ghv" ? "pcl-icf-ghv" : "pcl-icf";
    const std::string base = method + "_" + data.name() + "-" + o.split;
    const fs::path csv = o.out_dir / (base + ".csv");
    const std::string key = bopRunKey(data.name(), o.split, o.targets, o.seed);
    if (o.merge) {
      scoreAndWrite(data, o, mergeBopShards(o.out_dir, base, key), csv);
    } else if (o.shard.given) {
      writeBopShard(o.out_dir, base, o.shard, key, localizeImages(data, o));
      std::fprintf(stderr,
                   "shard %d/%d written to %s; join the shards with pcl_icf_bench --bop %s "
                   "--merge --out %s\n",
                   o.shard.index, o.shard.count, o.out_dir.string().c_str(),
                   o.root.string().c_str(), o.out_dir.string().c_str());
    } else {
      scoreAndWrite(data, o, localizeImages(data, o), csv);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcl_icf_bench: %s\n", e.what());
    return 2;
  }
}

}  // namespace pcl_icf_bench
