/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// The BOP pose errors, from their definitions (Hodan et al. 2020, section 2.2) and the BOP
// toolkit's conventions (bop_toolkit_lib: misc.get_symmetry_transformations, pose_error.vsd,
// mssd, mspd, visibility.estimate_visib_mask_*). No maintained C++ library computes them; the
// toolkit is Python with its own renderer. The rendering here is the project's own z-buffer
// (renderModelDepth), the one the depth verification uses.
#include <pcl/icf/evaluation/bop_pose_errors.h>

#include <pcl/icf/verification/depth_verification.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {
namespace evaluation {

namespace {

constexpr double kPi = 3.14159265358979323846;

void checkPointsAndSymmetries(const char* error, const std::vector<Eigen::Vector3d>& points,
                              const std::vector<Eigen::Isometry3d>& symmetries) {
  if (points.empty() || symmetries.empty())
    throw std::invalid_argument(std::string(error) +
                                ": needs the model's points and at least the identity among its "
                                "symmetries");
}

void checkSameSize(const DepthMap& a, const DepthMap& b, const char* what) {
  if (a.width != b.width || a.height != b.height ||
      a.z.size() != static_cast<std::size_t>(a.width) * static_cast<std::size_t>(a.height) ||
      b.z.size() != a.z.size())
    throw std::invalid_argument(std::string("vsd: the ") + what +
                                " image is not of the test image's size");
}

}  // namespace

std::vector<Eigen::Isometry3d> symmetryTransformations(
    const std::vector<Eigen::Isometry3d>& discrete,
    const std::vector<ContinuousSymmetry>& continuous, double max_step) {
  if (!(max_step > 0.0 && max_step <= 1.0))
    throw std::invalid_argument("symmetryTransformations: max_step " + std::to_string(max_step) +
                                " is not in (0, 1]");
  std::vector<Eigen::Isometry3d> with_identity = {Eigen::Isometry3d::Identity()};
  with_identity.insert(with_identity.end(), discrete.begin(), discrete.end());
  std::vector<Eigen::Isometry3d> turns;
  for (const ContinuousSymmetry& c : continuous) {
    if (!(c.axis.norm() > 0.0))
      throw std::invalid_argument("symmetryTransformations: a continuous symmetry's axis is 0");
    // The point farthest from the axis lies at most a diameter from it: a step of
    // 2 pi / ceil(pi / max_step) radians moves it at most max_step diameters.
    const int steps = static_cast<int>(std::ceil(kPi / max_step));
    for (int i = 0; i < steps; ++i) {
      Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
      turn.linear() = Eigen::AngleAxisd(2.0 * kPi * i / steps, c.axis.normalized()).matrix();
      turn.translation() = c.offset - turn.linear() * c.offset;
      turns.push_back(turn);
    }
  }
  if (turns.empty())
    return with_identity;
  std::vector<Eigen::Isometry3d> all;
  for (const auto& d : with_identity)
    for (const auto& t : turns)
      all.push_back(t * d);
  return all;
}

double mssd(const Eigen::Isometry3d& est, const Eigen::Isometry3d& gt,
            const std::vector<Eigen::Vector3d>& points,
            const std::vector<Eigen::Isometry3d>& symmetries) {
  checkPointsAndSymmetries("mssd", points, symmetries);
  double best = std::numeric_limits<double>::infinity();
  for (const auto& s : symmetries) {
    const Eigen::Isometry3d gt_s = gt * s;
    double worst = 0.0;
    for (const auto& x : points)
      worst = std::max(worst, (est * x - gt_s * x).norm());
    best = std::min(best, worst);
  }
  return best;
}

double mspd(const Eigen::Isometry3d& est, const Eigen::Isometry3d& gt, const Eigen::Matrix3d& K,
            const std::vector<Eigen::Vector3d>& points,
            const std::vector<Eigen::Isometry3d>& symmetries) {
  checkPointsAndSymmetries("mspd", points, symmetries);
  const auto project = [&](const Eigen::Vector3d& p) -> Eigen::Vector2d {
    return (K * p).hnormalized();
  };
  double best = std::numeric_limits<double>::infinity();
  for (const auto& s : symmetries) {
    const Eigen::Isometry3d gt_s = gt * s;
    double worst = 0.0;
    for (const auto& x : points)
      worst = std::max(worst, (project(est * x) - project(gt_s * x)).norm());
    best = std::min(best, worst);
  }
  return best;
}

DepthMap distanceImage(const DepthMap& depth, const Eigen::Matrix3d& K) {
  if (depth.width < 0 || depth.height < 0 ||
      depth.z.size() !=
          static_cast<std::size_t>(depth.width) * static_cast<std::size_t>(depth.height))
    throw std::invalid_argument("distanceImage: " + std::to_string(depth.z.size()) +
                                " depths for a " + std::to_string(depth.width) + " x " +
                                std::to_string(depth.height) + " image");
  DepthMap d = depth;
  for (int v = 0; v < depth.height; ++v)
    for (int u = 0; u < depth.width; ++u) {
      const double z = depth.at(u, v);
      const double x = (u - K(0, 2)) / K(0, 0), y = (v - K(1, 2)) / K(1, 1);
      d.z[static_cast<std::size_t>(v) * depth.width + u] =
          static_cast<float>(z * std::sqrt(x * x + y * y + 1.0));
    }
  return d;
}

std::vector<double> vsdFromDistances(const DepthMap& test, const DepthMap& est, const DepthMap& gt,
                                     double delta, const std::vector<double>& taus,
                                     double diameter) {
  checkSameSize(test, est, "estimate's");
  checkSameSize(test, gt, "truth's");
  const auto visible = [&](float model, float measured) {
    return model > 0.f && (measured == 0.f || model - measured <= delta);
  };
  std::size_t union_count = 0, inter_count = 0;
  std::vector<double> inter_distances;
  for (std::size_t p = 0; p < test.z.size(); ++p) {
    const bool visib_gt = visible(gt.z[p], test.z[p]);
    const bool visib_est = visible(est.z[p], test.z[p]) || (visib_gt && est.z[p] > 0.f);
    union_count += visib_gt || visib_est;
    if (visib_gt && visib_est) {
      ++inter_count;
      const double d = std::abs(static_cast<double>(gt.z[p]) - est.z[p]);
      inter_distances.push_back(diameter > 0.0 ? d / diameter : d);
    }
  }
  std::vector<double> errors;
  for (const double tau : taus) {
    if (union_count == 0) {
      errors.push_back(1.0);
      continue;
    }
    const auto off = static_cast<std::size_t>(std::count_if(
        inter_distances.begin(), inter_distances.end(), [&](double d) { return d >= tau; }));
    errors.push_back(static_cast<double>(off + union_count - inter_count) /
                     static_cast<double>(union_count));
  }
  return errors;
}

DepthMap renderDepth(const IcfModel& model, const Eigen::Isometry3d& model_to_camera,
                     const Eigen::Matrix3d& K, int width, int height) {
  PinholeIntrinsics intrinsics;
  intrinsics.fx = static_cast<float>(K(0, 0));
  intrinsics.fy = static_cast<float>(K(1, 1));
  intrinsics.cx = static_cast<float>(K(0, 2));
  intrinsics.cy = static_cast<float>(K(1, 2));
  intrinsics.width = width;
  intrinsics.height = height;
  intrinsics.validate();
  const ModelDepth rendered =
      renderModelDepth(model, model_to_camera.cast<float>(), intrinsics, false);
  DepthMap out{width, height, std::vector<float>(static_cast<std::size_t>(width) * height, 0.f)};
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
      if (rendered.covers(u, v))
        out.z[static_cast<std::size_t>(v) * width + u] = rendered.depthAt(u, v);
  return out;
}

std::vector<double> vsd(const IcfModel& model, const Eigen::Isometry3d& est,
                        const Eigen::Isometry3d& gt, const DepthMap& test_depth,
                        const Eigen::Matrix3d& K, double delta, const std::vector<double>& taus,
                        double diameter) {
  const int w = test_depth.width, h = test_depth.height;
  return vsdFromDistances(distanceImage(test_depth, K),
                          distanceImage(renderDepth(model, est, K, w, h), K),
                          distanceImage(renderDepth(model, gt, K, w, h), K), delta, taus, diameter);
}

}  // namespace evaluation
}  // namespace icf
}  // namespace pcl
