/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/common/io.h>
#include <pcl/common/transforms.h>
#include <pcl/icf/registration/iterative_closest_face.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pcl {
namespace icf {

template <typename PointT>
void MeshSurfaceSearch<PointT>::setInputCloud(const PointCloudConstPtr& cloud,
                                              const IndicesConstPtr& indices) {
  if (cloud && !cloud->empty()) {
    Base::setInputCloud(cloud, indices);
    return;
  }
  this->input_ = cloud;
  this->indices_ = indices;
}

template <typename PointT>
int MeshSurfaceSearch<PointT>::nearestKSearch(const PointT& point, int k, pcl::Indices& k_indices,
                                              std::vector<float>& k_sqr_distances) const {
  if (k != 1)
    return Base::nearestKSearch(point, k, k_indices, k_sqr_distances);
  k_indices.assign(1, -1);
  k_sqr_distances.assign(1, std::numeric_limits<float>::infinity());
  const Eigen::Vector3f p(point.x, point.y, point.z);
  if (!model_ || !p.allFinite())
    return 0;
  if (this->input_ && !this->input_->empty())
    Base::nearestKSearch(point, 1, k_indices, k_sqr_distances);
  const float d = model_->index().closestFace(p).distance;  // doc/icf.md eq. 3
  k_sqr_distances[0] = d * d;
  return 1;
}

}  // namespace icf

template <typename PointSource, typename Scalar>
IterativeClosestFace<PointSource, Scalar>::IterativeClosestFace() {
  reg_name_ = "IterativeClosestFace";
  setParams(params_);
  // An empty target rather than none: PCL's initCompute stops silently without one, and the
  // NoModel status would be unreachable. Its search method needs no kd-tree.
  target_ = pcl::make_shared<PointCloudSource>();
  this->setSearchMethodTarget(pcl::make_shared<icf::MeshSurfaceSearch<PointSource>>(nullptr), true);
}

template <typename PointSource, typename Scalar>
void IterativeClosestFace<PointSource, Scalar>::setInputTarget(
    const pcl::PolygonMesh::ConstPtr& mesh) {
  if (!mesh)
    throw std::invalid_argument("IterativeClosestFace::setInputTarget: null mesh");
  setInputModel(icf::IcfModel::build(*mesh, model_params_));
}

template <typename PointSource, typename Scalar>
void IterativeClosestFace<PointSource, Scalar>::setInputModel(
    const icf::IcfModel::ConstPtr& model) {
  if (!model)
    throw std::invalid_argument("IterativeClosestFace::setInputModel: null model");
  model_ = model;
  pcl::PointCloud<pcl::PointNormal> samples;
  samples.reserve(model->samples().size());
  for (const auto& s : model->samples()) {
    pcl::PointNormal p;
    p.getVector3fMap() = s.point;
    p.getNormalVector3fMap() = s.normal;
    samples.push_back(p);
  }
  auto target = pcl::make_shared<pcl::PointCloud<PointSource>>();
  pcl::copyPointCloud(samples, *target);
  // The tree is built here, once per model, and never rebuilt by initCompute.
  auto tree = pcl::make_shared<icf::MeshSurfaceSearch<PointSource>>(model);
  tree->setInputCloud(target);
  Base::setInputTarget(target);
  this->setSearchMethodTarget(tree, true);
}

template <typename PointSource, typename Scalar>
void IterativeClosestFace<PointSource, Scalar>::setInputTarget(const PointCloudTargetConstPtr&) {
  throw std::invalid_argument(
      "IterativeClosestFace::setInputTarget: the target must be a pcl::PolygonMesh "
      "(setInputTarget(PolygonMesh::ConstPtr) or setInputModel)");
}

template <typename PointSource, typename Scalar>
void IterativeClosestFace<PointSource, Scalar>::setParams(const icf::IcfParams& params) {
  params_ = params;
  const icf::RefinementParams& r = params.tuning().refinement;
  max_iterations_ = r.max_iterations;
  transformation_epsilon_ = r.transformation_epsilon;
  transformation_rotation_epsilon_ = std::cos(r.rotation_epsilon);
  euclidean_fitness_epsilon_ = r.euclidean_fitness_epsilon;
  corr_dist_threshold_ = r.initial_inlier_distance;
}

template <typename PointSource, typename Scalar>
icf::IcfParams IterativeClosestFace<PointSource, Scalar>::getParams() const {
  icf::IcfParams p = params_;
  icf::RefinementParams& r = p.tuning().refinement;
  r.max_iterations = max_iterations_;
  // PCL's conventions: a negative epsilon never stops (ours: 0); NaN stays NaN so that
  // validate() names it.
  r.transformation_epsilon = transformation_epsilon_ < 0.0 ? 0.0 : transformation_epsilon_;
  const double cos_epsilon = transformation_rotation_epsilon_;
  if (std::isnan(cos_epsilon))
    r.rotation_epsilon = cos_epsilon;
  else if (cos_epsilon > 0.0)
    r.rotation_epsilon = std::acos(std::min(1.0, cos_epsilon));
  else  // ICP: no rotation epsilon means a cosine of 1 - transformation_epsilon
    r.rotation_epsilon = std::acos(std::max(-1.0, 1.0 - r.transformation_epsilon));
  r.euclidean_fitness_epsilon = euclidean_fitness_epsilon_ < 0.0 ? 0.0 : euclidean_fitness_epsilon_;
  // ICP's "unbounded" default is sqrt(DBL_MAX): keep the radius a finite float.
  r.initial_inlier_distance = static_cast<float>(std::min(corr_dist_threshold_, 1e6));
  r.final_inlier_distance =
      std::min(params_.tuning().refinement.final_inlier_distance, r.initial_inlier_distance);
  return p;
}

template <typename PointSource, typename Scalar>
void IterativeClosestFace<PointSource, Scalar>::setCameraPose(
    const Eigen::Isometry3f& camera_to_source) {
  icf::validateRigidTransform(camera_to_source.matrix().cast<double>(),
                              "IterativeClosestFace::setCameraPose");
  camera_pose_ = camera_to_source;
}

template <typename PointSource, typename Scalar>
void IterativeClosestFace<PointSource, Scalar>::setCameraOrigin(const Eigen::Vector3f& origin) {
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = origin;
  setCameraPose(pose);
}

template <typename PointSource, typename Scalar>
Eigen::Isometry3f IterativeClosestFace<PointSource, Scalar>::getCameraPose() const {
  if (camera_pose_)
    return *camera_pose_;
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  if (!input_)
    return pose;
  const Eigen::Quaternionf& q = input_->sensor_orientation_;
  if (!q.coeffs().allFinite() || std::abs(q.norm() - 1.f) > 1e-3f)
    throw std::invalid_argument(
        "IterativeClosestFace: the source's sensor_orientation_ is not a unit quaternion");
  pose.linear() = q.normalized().toRotationMatrix();
  pose.translation() = input_->sensor_origin_.template head<3>();
  icf::validateRigidTransform(pose.matrix().cast<double>(),
                              "IterativeClosestFace: the source's sensor pose");
  return pose;
}

template <typename PointSource, typename Scalar>
double IterativeClosestFace<PointSource, Scalar>::getFitnessScore(double max_range) {
  if (!(max_range > 0.0)) {
    std::ostringstream msg;
    msg << "IterativeClosestFace::getFitnessScore: max_range = " << max_range
        << ": must be positive";
    throw std::invalid_argument(msg.str());
  }
  if (!input_)
    throw std::invalid_argument("IterativeClosestFace::getFitnessScore: no source");
  return Base::getFitnessScore(max_range);  // point-to-face through MeshSurfaceSearch
}

template <typename PointSource, typename Scalar>
std::vector<Eigen::Vector3f> IterativeClosestFace<PointSource, Scalar>::finitePoints(
    const PointCloudSource& cloud) const {
  std::vector<Eigen::Vector3f> points;
  auto add = [&points](const PointSource& p) {
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      points.emplace_back(p.x, p.y, p.z);
  };
  if (input_ && &cloud == input_.get() && indices_) {
    points.reserve(indices_->size());
    for (const auto i : *indices_)
      add(cloud[i]);
  } else {
    points.reserve(cloud.size());
    for (const auto& p : cloud)
      add(p);
  }
  return points;
}

template <typename PointSource, typename Scalar>
std::size_t IterativeClosestFace<PointSource, Scalar>::getCorrespondenceCount() const {
  if (!correspondences_) {
    const bool posed =
        result_.status == icf::IcfStatus::Accepted || result_.status == icf::IcfStatus::Rejected;
    correspondences_ =
        posed && model_ && aligned_source_
            ? icf::countPointsNearSurface(model_->index(), finitePoints(*aligned_source_),
                                          Eigen::Isometry3f(result_.scene_to_model),
                                          aligned_radius_, params_.threads)
            : 0;
  }
  return *correspondences_;
}

template <typename PointSource, typename Scalar>
void IterativeClosestFace<PointSource, Scalar>::computeTransformation(PointCloudSource& output,
                                                                      const Matrix4& guess) {
  result_ = icf::IcfResult();
  correspondences_.reset();
  aligned_source_ = input_;
  icf::validateRigidTransform(guess.template cast<double>(),
                              "IterativeClosestFace::align: the guess");
  if (!(corr_dist_threshold_ > 0.0)) {
    std::ostringstream msg;
    msg << "IterativeClosestFace::align: setMaxCorrespondenceDistance(" << corr_dist_threshold_
        << "): must be positive";
    throw std::invalid_argument(msg.str());
  }
  const icf::IcfParams params = getParams();
  params.validate();
  output = *input_;  // as ICP: the whole source, moved below
  if (!model_) {
    result_.status = icf::IcfStatus::NoModel;
    return;  // converged_ false, the final transformation the identity: PCL's initial state
  }
  const std::vector<Eigen::Vector3f> points = finitePoints(*input_);
  const Eigen::Vector3f camera = getCameraPose().translation();

  icf::IterationCallback callback;
  if (update_visualizer_)
    callback = [this](const Eigen::Isometry3f& T, int) {
      PointCloudSource moved;
      pcl::transformPointCloud(*input_, moved, T.matrix());
      const pcl::Indices none;
      update_visualizer_(moved, none, *target_, none);
    };

  const Eigen::Isometry3f guess_iso(guess.template cast<float>());
  const bool identity = guess.template cast<double>().isIdentity(1e-12);
  const bool from_guess =
      guess_policy_ == GuessPolicy::Always || (guess_policy_ != GuessPolicy::Never && !identity);
  const float radius = aligned_radius_ = params.tuning().refinement.initial_inlier_distance;
  icf::PoseEstimateOptions search_options;
  search_options.callback = callback;
  icf::PoseEstimateOptions from_guess_options = search_options;
  from_guess_options.guess = guess_iso;
  if (from_guess) {
    result_ = icf::estimatePose(*model_, points, camera, params, from_guess_options);
  } else {
    // The identity first (see the class comment) when the source already lies on the model.
    std::optional<icf::IcfResult> local;
    if (guess_policy_ == GuessPolicy::IdentityRefinedFirst &&
        icf::countPointsNearSurface(model_->index(), points, Eigen::Isometry3f::Identity(), radius,
                                    params.threads) >= params.acceptance.min_inliers) {
      local = icf::estimatePose(*model_, points, camera, params, from_guess_options);
      local->method = "identity+icf";
    }
    if (local && local->accepted()) {
      result_ = *local;
    } else {
      result_ = icf::estimatePose(*model_, points, camera, params, search_options);
      // Neither accepted: the pose that covers more of the visible surface, as estimatePose
      // chooses between the search and its fallback.
      if (local) {
        const double total_ms = result_.time_ms + local->time_ms;
        if (!result_.accepted() &&
            local->quality.surface_coverage > result_.quality.surface_coverage)
          result_ = *local;
        result_.time_ms = total_ms;
      }
    }
  }

  nr_iterations_ = result_.refinement_iterations;
  final_transformation_ = transformation_ = result_.scene_to_model.template cast<Scalar>();
  previous_transformation_ = final_transformation_;
  converged_ =
      from_guess ? getCorrespondenceCount() >= min_number_correspondences_ : result_.accepted();
  if constexpr (pcl::traits::has_normal_v<PointSource>)
    pcl::transformPointCloudWithNormals(*input_, output, final_transformation_);
  else
    pcl::transformPointCloud(*input_, output, final_transformation_);
}

}  // namespace pcl
