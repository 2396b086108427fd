/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_bench's non-PCL peers, on the same clusters as the other methods:
//   o3d-ransac+icp  Open3D 0.16: FPFH, RegistrationRANSACBasedOnFeatureMatching (mutual filter,
//                   edge-length 0.9 and distance checkers, 100,000 iterations, confidence
//                   0.999), then point-to-plane RegistrationICP
//   o3d-fgr+icp     Open3D 0.16: FPFH, FastGlobalRegistrationBasedOnFeatureMatching, then the
//                   same ICP
//   ppf+icp         OpenCV 4.6 contrib: cv::ppf_match_3d::PPF3DDetector (Drost et al. 2010),
//                   then cv::ppf_match_3d::ICP on its 5 best-voted poses, as OpenCV's sample
// Parameters follow Open3D's global registration tutorial and OpenCV's surface-matching sample,
// scaled to the voxel size the PCL pipelines use (icf::SacParams::voxel_size, 5 mm): normals
// over 2 voxels, FPFH over 5, RANSAC inliers within 1.5 voxels, FGR within 0.5. The final ICP
// accepts pairs within 4 voxels (2 cm, as the PCL pipelines' ICP) instead of the tutorial's
// 0.4 voxel, which cannot pull in a start 1 cm off. Compiled only when Open3D and OpenCV's
// surface_matching are found (PCL_ICF_BENCH_PEERS); this header is then the only way in, so
// their headers stay out of the rest of the bench.
#pragma once

#include "bench_methods.h"

#include <memory>
#include <string>
#include <vector>

namespace pcl_icf_tools {
namespace bench {

/** The peers' methods, in the order the bench lists them. */
const std::vector<std::string>& peerMethods();

/** The peers' per-model data (down-sampled model with FPFH for Open3D, the trained PPF
 * detector for OpenCV), built once per model; \a prepared_ms receives the build time of each
 * (Open3D, then OpenCV). */
std::shared_ptr<const PeerModel> preparePeerModel(const PreparedModel& model, double voxel_size,
                                                  double ppf_sampling, int threads,
                                                  std::vector<double>& prepared_ms);

/** Runs peer method \a method (one of peerMethods()) on \a cluster; \a seed seeds Open3D's
 * random generator before each call, and its RANSAC runs on one thread, so a run is
 * repeatable (its parallel loop draws from one shared generator in thread order). FPFH,
 * normals and PPF's voting use \a threads (0: all cores). */
MethodRun runPeer(const std::string& method, const CloudXYZ::Ptr& cluster,
                  const PreparedModel& model, double voxel_size, int seed, int threads);

}  // namespace bench
}  // namespace pcl_icf_tools
