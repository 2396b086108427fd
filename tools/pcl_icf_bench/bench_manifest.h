/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_bench's manifest: one case per line (doc/DATASETS.md).
#pragma once

#include "synthetic/pose_error.h"

#include <Eigen/Geometry>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace pcl_icf_tools {
namespace bench {

/** Bad usage, manifest or data: the benchmark stops with exit code 2. */
class BadInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/** One line of a manifest (doc/DATASETS.md). */
struct CaseSpec {
  std::string name, group;
  std::filesystem::path scene, model;
  double scale = 1.0;                                       ///< model units to metres
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();  ///< model (metres) -> scene
  /** truth=none: the model is absent from the scene (a target-absent case); truth is then the
   * identity and unused. A method is right on such a case when it says "not found". */
  bool absent = false;
  std::string symmetry_spec = "none";
  /** The frame the errors are measured in, in the model frame: its origin (center=) is the
   * point whose translation error counts and the symmetry's centre, its axes (axes=) the
   * symmetry's axes. Identity by default. */
  Eigen::Isometry3d reference = Eigen::Isometry3d::Identity();
  /** center= was given; otherwise the errors are measured at the model's bounding-box centre
   * (PreparedModel::box_centre). */
  bool center_set = false;
  std::string cluster = "all";  ///< all | indices:FILE | crop:MARGIN
  std::filesystem::path indices;
  double crop_margin = 0.0;
  bool camera_set = false;
  Eigen::Vector3f camera = Eigen::Vector3f::Zero();
  std::string source;  ///< "manifest:line" for messages
};

/** The symmetry group of a manifest spec: none, box:SX,SY,SZ, prism:N, cylinder,
 * cylinder:noflip. BadInput (naming \a where) otherwise. */
pcl::icf::synthetic::Symmetry parseSymmetry(const std::string& spec, const std::string& where);

/** Every case of a manifest, paths resolved against its folder; BadInput naming the line on
 * any malformed or repeated entry. */
std::vector<CaseSpec> readManifest(const std::filesystem::path& path);

}  // namespace bench
}  // namespace pcl_icf_tools
