/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The BOP benchmark's three pose errors (Hodan et al., "BOP Challenge 2020 on 6D Object
 * Localization", ECCV workshops 2020, section 2.2): VSD, the Visible Surface Discrepancy,
 * MSSD, the Maximum Symmetry-aware Surface Distance, and MSPD, the Maximum Symmetry-aware
 * Projection Distance, as the BOP toolkit computes them, and the set of symmetry
 * transformations they take from a model's `models_info.json` entry.
 *
 * Lengths in any one unit (BOP's files are in millimetres; pcl_icf's clouds and models in
 * metres): the errors come out in it (VSD is a fraction, MSPD in pixels). A pose maps model
 * coordinates to camera coordinates (BOP's cam_R_m2c, cam_t_m2c). */

#include <pcl/icf/registration/icf_model.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace pcl {
namespace icf {
namespace evaluation {

/** \brief A continuous rotational symmetry: every rotation about \a axis through \a offset
 * (model frame) maps the model onto itself (BOP's `symmetries_continuous`). */
struct ContinuousSymmetry {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
};

/** \brief The symmetry transformations S of a model (x and S x are the same surface point): the
 * identity, each discrete one, and each continuous one discretised so that the point farthest
 * from its axis travels at most \a max_step diameters between neighbouring rotations (BOP's
 * evaluation uses 0.01: ceil(pi / 0.01) = 315 rotations), composed with the discrete ones as
 * the BOP toolkit does (continuous after discrete). \throws std::invalid_argument for a
 * \a max_step outside (0, 1] or an axis of zero length. */
std::vector<Eigen::Isometry3d> symmetryTransformations(
    const std::vector<Eigen::Isometry3d>& discrete,
    const std::vector<ContinuousSymmetry>& continuous, double max_step = 0.01);

/** \brief MSSD: min over the symmetries S of max over the model's \a points x of
 * |est x - gt S x|. \throws std::invalid_argument for no points or no symmetries (give at least
 * the identity: symmetryTransformations does). */
double mssd(const Eigen::Isometry3d& est, const Eigen::Isometry3d& gt,
            const std::vector<Eigen::Vector3d>& points,
            const std::vector<Eigen::Isometry3d>& symmetries);

/** \brief MSPD: min over the symmetries S of max over the model's \a points x of the image
 * distance (pixels) between the projections through \a K of est x and gt S x. \throws as
 * mssd. */
double mspd(const Eigen::Isometry3d& est, const Eigen::Isometry3d& gt, const Eigen::Matrix3d& K,
            const std::vector<Eigen::Vector3d>& points,
            const std::vector<Eigen::Isometry3d>& symmetries);

/** \brief A depth image: z per pixel, row-major, 0 where nothing was measured or rendered
 * (the BOP convention). */
struct DepthMap {
  int width = 0, height = 0;
  std::vector<float> z;
  float at(int u, int v) const { return z[static_cast<std::size_t>(v) * width + u]; }
};

/** \brief The distance from the camera centre of each pixel's point (BOP's distance image):
 * z |(u - cx) / fx, (v - cy) / fy, 1|, 0 where \a depth is 0. \throws std::invalid_argument
 * when \a depth's values do not number its pixels. */
DepthMap distanceImage(const DepthMap& depth, const Eigen::Matrix3d& K);

/** \brief VSD from distance images (distanceImage): the test image \a test, the model rendered
 * at the estimate \a est and at the truth \a gt. A rendered pixel is visible where the test
 * distance is at most \a delta in front of it or missing (BOP 2019's visibility); the estimate
 * is also visible wherever the truth is and it covers the pixel. The error for each tolerance
 * tau of \a taus is the share of the two visible masks' union that is either outside their
 * intersection or off by tau or more; 1 when both masks are empty. With \a diameter > 0 the
 * distances are divided by it first (BOP 2019: taus are fractions of the diameter).
 * \throws std::invalid_argument for images of different sizes. */
std::vector<double> vsdFromDistances(const DepthMap& test, const DepthMap& est, const DepthMap& gt,
                                     double delta, const std::vector<double>& taus,
                                     double diameter);

/** \brief The depth image of \a model at \a model_to_camera (metres) through \a K, of
 * \a width x \a height: z of the nearest camera-facing face per pixel centre, 0 elsewhere. */
DepthMap renderDepth(const IcfModel& model, const Eigen::Isometry3d& model_to_camera,
                     const Eigen::Matrix3d& K, int width, int height);

/** \brief VSD of \a est against \a gt for \a model seen in the depth image \a test_depth
 * (metres, 0 where missing) through \a K: both poses rendered (renderDepth), all three turned
 * into distance images, then vsdFromDistances with \a delta, \a taus and \a diameter
 * (metres). */
std::vector<double> vsd(const IcfModel& model, const Eigen::Isometry3d& est,
                        const Eigen::Isometry3d& gt, const DepthMap& test_depth,
                        const Eigen::Matrix3d& K, double delta, const std::vector<double>& taus,
                        double diameter);

}  // namespace evaluation
}  // namespace icf
}  // namespace pcl
