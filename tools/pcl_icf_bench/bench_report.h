/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_bench's results: one row per case and method, the chapter-7 statistics per group
// and method, and the outputs (CSV, markdown, gnuplot bar charts).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace pcl_icf_tools {
namespace bench {

/** The project's rule for every suite: success when the model's centre (its bounding box's, or
 * the manifest's center=) lies within kSuccessTranslation of the truth and ADD-S is below
 * kSuccessAddS x the model's diameter (the YCB-Video and BOP family of metrics: a turn that maps
 * the object onto itself counts). The strict rule beside it also bounds the symmetry-aware
 * rotation error by kSuccessRotation. */
constexpr double kSuccessTranslation = 0.01;  ///< metres
constexpr double kSuccessAddS = 0.1;          ///< of the model's diameter
constexpr double kSuccessRotation = 5.0;      ///< degrees, the strict rule

/** One method on one case. */
struct Row {
  std::string case_name, group, method;
  std::size_t points = 0;
  double t_mm = 0, r_deg = 0, r_nosym_deg = 0, adds_mm = 0, ms = 0;
  bool success = false, converged = false;
  bool strict_success = false;  ///< success and the rotation within kSuccessRotation
  /** success, or one of the method's reported alternatives is one (icf-scene's ambiguity). */
  bool success_among_alternatives = false;
  /** A target-absent case (truth=none): no errors are measured and success stays false; the
   * method is right when it says not found (converged false), else the row is a false pose. */
  bool absent = false, false_pose = false;
  std::string detail;
  double confidence = std::numeric_limits<double>::quiet_NaN();  ///< icf-scene's, see MethodRun
  std::string verification;                                      ///< icf-scene's terms
  Eigen::Matrix4f object_pose = Eigen::Matrix4f::Identity();     ///< the estimate, model -> scene
};

/** A group's (or all groups') statistics for one method. Success and errors are over the
 * cases with the target present (n); false poses over the target-absent ones (absent); the
 * median time over all. */
struct Summary {
  std::size_t n = 0;
  double success = 0;
  std::size_t absent = 0, false_poses = 0;
  double false_pose_rate = 0;  ///< false_poses / absent (0 without absent cases)
  double t_mean = 0, t_median = 0, t_std = 0;
  double r_mean = 0, r_median = 0, r_std = 0;
  double adds_mean = 0, adds_median = 0, time_median = 0;
};

/** The median (mean of the middle two for an even count); 0 for none. */
double median(std::vector<double> v);

/** Success rate, mean / median / sample standard deviation of the errors and ADD-S over the
 * present-target rows of \a rows, the false-pose rate over its absent-target rows and the
 * median time over all of them. */
Summary summarize(const std::vector<const Row*>& rows);

/** Rows of one method, of one group ("" for all groups). */
using RowSelector =
    std::function<std::vector<const Row*>(const std::string& group, const std::string& method)>;

/** NAME_cases.csv: one line per case and method, with the estimated pose. */
void writeCasesCsv(const std::filesystem::path& file, const std::vector<Row>& rows);

/** NAME_summary.csv: per group (and ALL) and method, the Summary. */
void writeSummaryCsv(const std::filesystem::path& file, const std::vector<std::string>& groups,
                     const std::vector<std::string>& methods, const RowSelector& rowsOf);

/** The markdown table of every method with rows (one group's, or all groups'). */
std::string formatTable(const std::vector<std::string>& methods,
                        const std::function<std::vector<const Row*>(const std::string&)>& rowsOf);

/** Bar charts like the thesis's figures 7.5 (mean) and 7.6 (standard deviation): per group
 * and method, translation error (a) above rotation error (b); log scale, since failures are
 * two orders of magnitude above successes. */
void writePlots(const std::filesystem::path& data_dir, const std::filesystem::path& dir,
                const std::string& name, const std::vector<std::string>& groups,
                const std::vector<std::string>& methods, const RowSelector& rowsOf);

}  // namespace bench
}  // namespace pcl_icf_tools
