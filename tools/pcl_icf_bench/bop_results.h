/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The results of pcl_icf_bench --bop: BOP's results CSV (bop_toolkit's
 * docs/bop_challenge_*: scene_id,im_id,obj_id,score,R,t,time; R row-major and t in mm,
 * space-separated; time per image in seconds, the same on every row of an image), and the
 * shards a run spread over several processes writes and --merge joins. */

#include <Eigen/Geometry>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace pcl_icf_bench {

/** One row of the results CSV. */
struct BopEstimate {
  int scene_id = 0, im_id = 0, obj_id = 0;
  double score = 0.0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< model -> camera, mm
  double seconds = 0.0;
};

/** Sorts rows by scene, image, object, then decreasing score (ties by translation): the order
 * of every CSV written, so one process and any number of shards give the same file. */
void sortEstimates(std::vector<BopEstimate>& rows);

/** How writeBopCsv writes a pose: as BOP's CSV (the nearest rotation, 9 decimals; translation
 * and score 6) or exactly (every number to 17 significant digits, the rotation as computed), for
 * the shard files a merge reads back, so that merged shards write what one process writes. */
enum class CsvPoses { kBop, kExact };

/** Writes \a rows as BOP's CSV at \a path: to a temporary beside it, renamed when complete.
 * \throws std::runtime_error when it cannot be written. */
void writeBopCsv(const std::filesystem::path& path, const std::vector<BopEstimate>& rows,
                 CsvPoses poses = CsvPoses::kBop);

/** Reads a results CSV as writeBopCsv writes it. \throws pcl::icf::io::FileError naming the
 * file and line of a malformed row. */
std::vector<BopEstimate> readBopCsv(const std::filesystem::path& path);

/** Shard K of N (K counted from 1): the images whose index in (scene, image) order is K - 1
 * modulo N. */
struct BopShard {
  int index = 1, count = 1;
  bool given = false;  ///< --shard or the environment set it
  bool has(std::size_t image_index) const {
    return static_cast<int>(image_index % static_cast<std::size_t>(count)) == index - 1;
  }
};

/** Parses "K/N" with 1 <= K <= N. \throws pcl_icf_tools::UsageError otherwise. */
BopShard parseShard(const std::string& text);

/** The shard of this process from Open MPI's mpirun (OMPI_COMM_WORLD_RANK, _SIZE: K = rank + 1)
 * or a Slurm job array (SLURM_ARRAY_TASK_ID, _COUNT and _MIN: K = id - min + 1), Open MPI's
 * first; not given when neither is set. \throws pcl_icf_tools::UsageError naming the variable
 * that does not make a shard. */
BopShard shardFromEnvironment();

/** What makes two shards parts of one run: the dataset's name, the split, the targets file's
 * bytes and the seed, hashed (FNV-1a, 64 bits, as hex). */
std::string bopRunKey(const std::string& dataset, const std::string& split,
                      const std::filesystem::path& targets, unsigned seed);

/** The results of shard \a shard: its CSV (\a base + ".shard-K-of-N.csv") and beside it a JSON
 * record of the run key, the shard and its row count, written last so a shard without its record
 * is an unfinished one. */
void writeBopShard(const std::filesystem::path& out_dir, const std::string& base,
                   const BopShard& shard, const std::string& run_key,
                   const std::vector<BopEstimate>& rows);

/** The rows of all shards of \a base in \a out_dir, sorted. \throws pcl::icf::io::FileError
 * when there are none, when one is missing or unfinished, when their counts differ or when one
 * is of another run (its key is not \a run_key). */
std::vector<BopEstimate> mergeBopShards(const std::filesystem::path& out_dir,
                                        const std::string& base, const std::string& run_key);

}  // namespace pcl_icf_bench
