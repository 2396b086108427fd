/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "bop_results.h"

#include <Eigen/SVD>

#include "common/arguments.h"

#include <pcl/icf/io/mesh_io.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <tuple>
#include <utility>

namespace pcl_icf_bench {

namespace {

namespace fs = std::filesystem;
using pcl::icf::io::FileError;
using pcl_icf_tools::UsageError;

/** Writes \a text to \a path through a temporary renamed into place. */
void writeWhole(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".part";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out)
      throw std::runtime_error(path.string() + ": cannot be written");
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec)
    throw std::runtime_error(path.string() + ": cannot be written (" + ec.message() + ")");
}

std::vector<double> numbersOf(const std::string& field) {
  std::vector<double> v;
  std::istringstream in(field);
  for (std::string word; in >> word;) {
    char* end = nullptr;
    v.push_back(std::strtod(word.c_str(), &end));
    if (end == word.c_str() || *end != '\0')
      return {};
  }
  return v;
}

int integerOf(const std::string& field) {
  char* end = nullptr;
  const long v = std::strtol(field.c_str(), &end, 10);
  if (field.empty() || *end != '\0' || v < 0 || v > 1000000000)
    return -1;
  return static_cast<int>(v);
}

/** A positive integer from the environment variable \a name, or -1 when it is not set. */
long environmentInteger(const char* name, long min) {
  const char* text = std::getenv(name);
  if (!text)
    return -1;
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (*text == '\0' || *end != '\0' || v < min)
    throw UsageError(std::string(name) + "=" + text +
                     " is not a shard number (an integer >= " + std::to_string(min) + ")");
  return v;
}

BopShard checkedShard(long index, long count, const std::string& what) {
  if (count < 1 || index < 1 || index > count)
    throw UsageError(what + ": shard " + std::to_string(index) + " of " + std::to_string(count) +
                     " (give K/N with 1 <= K <= N)");
  BopShard s;
  s.index = static_cast<int>(index);
  s.count = static_cast<int>(count);
  s.given = true;
  return s;
}

std::string shardName(const std::string& base, const BopShard& shard, const char* ext) {
  return base + ".shard-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count) +
         ext;
}

}  // namespace

void sortEstimates(std::vector<BopEstimate>& rows) {
  const auto key = [](const BopEstimate& e) {
    const Eigen::Vector3d t = e.pose.translation();
    return std::make_tuple(e.scene_id, e.im_id, e.obj_id, -e.score, t.x(), t.y(), t.z());
  };
  std::stable_sort(rows.begin(), rows.end(),
                   [&](const BopEstimate& a, const BopEstimate& b) { return key(a) < key(b); });
}

void writeBopCsv(const fs::path& path, const std::vector<BopEstimate>& rows, CsvPoses poses) {
  std::string text = "scene_id,im_id,obj_id,score,R,t,time\n";
  char buf[768];
  for (const BopEstimate& e : rows) {
    Eigen::Matrix3d R = e.pose.linear();
    const Eigen::Vector3d t = e.pose.translation();
    if (poses == CsvPoses::kBop) {
      // The nearest rotation (U V^T of the SVD): the localizer's rotations are computed in float
      // and stray from orthonormal by up to about 1e-6, which the 9 decimals written would show.
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
      R = svd.matrixU() * svd.matrixV().transpose();
      std::snprintf(
          buf, sizeof buf,
          "%d,%d,%d,%.6f,%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f,%.6f %.6f %.6f,%.3f\n",
          e.scene_id, e.im_id, e.obj_id, e.score, R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1),
          R(1, 2), R(2, 0), R(2, 1), R(2, 2), t.x(), t.y(), t.z(), e.seconds);
    } else {
      std::snprintf(buf, sizeof buf,
                    "%d,%d,%d,%.17g,%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g,"
                    "%.17g %.17g %.17g,%.17g\n",
                    e.scene_id, e.im_id, e.obj_id, e.score, R(0, 0), R(0, 1), R(0, 2), R(1, 0),
                    R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2), t.x(), t.y(), t.z(), e.seconds);
    }
    text += buf;
  }
  writeWhole(path, text);
}

std::vector<BopEstimate> readBopCsv(const fs::path& path) {
  std::ifstream in(path);
  if (!in)
    throw FileError(path.string() + ": cannot be read");
  std::string line;
  if (!std::getline(in, line) || line != "scene_id,im_id,obj_id,score,R,t,time")
    throw FileError(path.string() +
                    ": line 1 is not BOP's header "
                    "scene_id,im_id,obj_id,score,R,t,time");
  std::vector<BopEstimate> rows;
  for (int number = 2; std::getline(in, line); ++number) {
    std::vector<std::string> f;
    std::stringstream fields(line);
    for (std::string part; std::getline(fields, part, ',');)
      f.push_back(part);
    const std::vector<double> score = f.size() == 7 ? numbersOf(f[3]) : std::vector<double>{};
    const std::vector<double> r = f.size() == 7 ? numbersOf(f[4]) : std::vector<double>{};
    const std::vector<double> t = f.size() == 7 ? numbersOf(f[5]) : std::vector<double>{};
    const std::vector<double> time = f.size() == 7 ? numbersOf(f[6]) : std::vector<double>{};
    BopEstimate e;
    if (f.size() == 7) {
      e.scene_id = integerOf(f[0]);
      e.im_id = integerOf(f[1]);
      e.obj_id = integerOf(f[2]);
    }
    if (f.size() != 7 || e.scene_id < 0 || e.im_id < 0 || e.obj_id < 0 || score.size() != 1 ||
        r.size() != 9 || t.size() != 3 || time.size() != 1)
      throw FileError(path.string() + ": line " + std::to_string(number) +
                      " is not a row of scene_id,im_id,obj_id,score,R (9),t (3),time");
    e.score = score[0];
    e.pose.linear() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(r.data());
    e.pose.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
    e.seconds = time[0];
    rows.push_back(e);
  }
  return rows;
}

BopShard parseShard(const std::string& text) {
  const std::size_t slash = text.find('/');
  const auto part = [&](const std::string& s) {
    return pcl_icf_tools::parseInteger("--shard", s, 0, 1000000);
  };
  if (slash == std::string::npos)
    throw UsageError("--shard " + text + ": give K/N, shard K of N counted from 1");
  return checkedShard(part(text.substr(0, slash)), part(text.substr(slash + 1)), "--shard " + text);
}

/** The launcher's (index, count) from two variables: both set, or neither ({-1, -1}). */
std::pair<long, long> environmentPair(const char* index_name, const char* count_name) {
  const long index = environmentInteger(index_name, 0);
  const long count = environmentInteger(count_name, 1);
  if ((index < 0) != (count < 0))
    throw UsageError(std::string(index_name) + " and " + count_name +
                     ": one is set without the other");
  return {index, count};
}

BopShard shardFromEnvironment() {
  const auto [rank, size] = environmentPair("OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE");
  if (rank >= 0)
    return checkedShard(rank + 1, size, "OMPI_COMM_WORLD_RANK/SIZE");
  const auto [id, count] = environmentPair("SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT");
  if (id >= 0) {
    const long min = environmentInteger("SLURM_ARRAY_TASK_MIN", 0);
    return checkedShard(id - std::max(min, 0L) + 1, count, "SLURM_ARRAY_TASK_ID/COUNT/MIN");
  }
  return {};
}

std::string bopRunKey(const std::string& dataset, const std::string& split, const fs::path& targets,
                      unsigned seed) {
  std::ifstream in(targets, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string text =
      "pcl_icf_bench --bop\n" + dataset + "\n" + split + "\n" + std::to_string(seed) + "\n" + bytes;
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a offset basis
  for (const unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;  // FNV prime
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

void writeBopShard(const fs::path& out_dir, const std::string& base, const BopShard& shard,
                   const std::string& run_key, const std::vector<BopEstimate>& rows) {
  writeBopCsv(out_dir / shardName(base, shard, ".csv"), rows, CsvPoses::kExact);
  const nlohmann::json record = {
      {"run_key", run_key}, {"shard", shard.index}, {"shards", shard.count}, {"rows", rows.size()}};
  writeWhole(out_dir / shardName(base, shard, ".json"), record.dump(2) + "\n");
}

std::vector<BopEstimate> mergeBopShards(const fs::path& out_dir, const std::string& base,
                                        const std::string& run_key) {
  // Every file BASE.shard-K-of-N.{csv,json} of the folder.
  const std::regex name(std::regex_replace(base, std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") +
                        R"(\.shard-(\d+)-of-(\d+)\.(csv|json))");
  std::map<std::pair<int, int>, int> found;  // (K, N) -> 1 csv | 2 json
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(out_dir, ec)) {
    std::smatch m;
    const std::string file = entry.path().filename().string();
    if (std::regex_match(file, m, name))
      found[{std::stoi(m[1]), std::stoi(m[2])}] |= m[3] == "csv" ? 1 : 2;
  }
  const std::string where = (out_dir / (base + ".shard-*")).string();
  if (found.empty())
    throw FileError(where + ": no shards to merge (run the shards first, e.g. --shard K/N)");
  const int count = found.begin()->first.second;
  std::vector<BopEstimate> rows;
  for (const auto& [shard_id, parts] : found) {
    BopShard shard;
    shard.index = shard_id.first;
    shard.count = shard_id.second;
    const fs::path csv = out_dir / shardName(base, shard, ".csv");
    const fs::path json = out_dir / shardName(base, shard, ".json");
    if (shard.count != count)
      throw FileError(where + ": shards of " + std::to_string(count) + " and of " +
                      std::to_string(shard.count) + " processes are mixed; clear the folder");
    if (parts != 3)
      throw FileError((parts == 1 ? json : csv).string() + ": missing, the shard did not finish");
    std::size_t expected_rows = 0;
    try {
      nlohmann::json record;
      std::ifstream in(json);
      record = nlohmann::json::parse(in);
      if (record.at("run_key").get<std::string>() != run_key)
        throw FileError(json.string() + ": run_key " + record.at("run_key").get<std::string>() +
                        " is of another run (dataset, split, targets or seed differ) than " +
                        run_key);
      if (record.at("shard").get<int>() != shard.index ||
          record.at("shards").get<int>() != shard.count)
        throw FileError(json.string() + ": shard and shards disagree with the file's name");
      expected_rows = record.at("rows").get<std::size_t>();
    } catch (const nlohmann::json::exception& e) {
      throw FileError(json.string() + ": not a shard record (" + e.what() + ")");
    }
    std::vector<BopEstimate> part = readBopCsv(csv);
    if (part.size() != expected_rows)
      throw FileError(csv.string() + ": " + std::to_string(part.size()) + " rows, its record " +
                      json.string() + " says " + std::to_string(expected_rows));
    rows.insert(rows.end(), part.begin(), part.end());
  }
  for (int k = 1; k <= count; ++k)
    if (!found.count({k, count}))
      throw FileError(where + ": shard " + std::to_string(k) + " of " + std::to_string(count) +
                      " is missing");
  sortEstimates(rows);
  return rows;
}

}  // namespace pcl_icf_bench
