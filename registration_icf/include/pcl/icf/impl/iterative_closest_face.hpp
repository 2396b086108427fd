/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/common/io.h>
#include <pcl/common/transforms.h>
#include <pcl/icf/iterative_closest_face.h>

#include <cmath>
#include <stdexcept>

namespace pcl {

template <typename PointSource, typename Scalar>
IterativeClosestFace<PointSource, Scalar>::IterativeClosestFace() {
  reg_name_ = "IterativeClosestFace";
  max_iterations_ = params_.refinement.max_iterations;
  transformation_epsilon_ = params_.refinement.transformation_epsilon;
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
  Base::setInputTarget(target);
}

template <typename PointSource, typename Scalar>
void IterativeClosestFace<PointSource, Scalar>::setInputTarget(const PointCloudTargetConstPtr&) {
  throw std::invalid_argument(
      "IterativeClosestFace::setInputTarget: the target must be a pcl::PolygonMesh "
      "(setInputTarget(PolygonMesh::ConstPtr) or setInputModel)");
}

template <typename PointSource, typename Scalar>
void IterativeClosestFace<PointSource, Scalar>::computeTransformation(PointCloudSource& output,
                                                                      const Matrix4& guess) {
  result_ = icf::IcfResult();
  if (!model_) {
    result_.status = icf::IcfStatus::NoModel;
    return;
  }
  icf::IcfParams params = params_;
  params.refinement.max_iterations = max_iterations_;
  params.refinement.transformation_epsilon = std::max(0.0, transformation_epsilon_);
  if (transformation_rotation_epsilon_ > 0.0 && transformation_rotation_epsilon_ <= 1.0)
    params.refinement.rotation_epsilon = std::acos(transformation_rotation_epsilon_);
  params.refinement.euclidean_fitness_epsilon = std::max(0.0, euclidean_fitness_epsilon_);

  std::vector<Eigen::Vector3f> points;
  points.reserve(indices_->size());
  for (const auto i : *indices_) {
    const auto& p = (*input_)[i];
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      points.emplace_back(p.x, p.y, p.z);
  }
  const Eigen::Vector3f camera = camera_set_ ? camera_ : input_->sensor_origin_.template head<3>();

  const Eigen::Matrix4f guess_f = guess.template cast<float>();
  if (!guess_f.allFinite())
    throw std::invalid_argument("IterativeClosestFace::align: the guess has a non-finite entry");
  const bool identity = guess_f.isIdentity(1e-12f);
  const bool use_guess = guess_policy_ == GuessPolicy::Always ||
                         (guess_policy_ == GuessPolicy::IdentityMeansNone && !identity);
  const Eigen::Isometry3f guess_iso(guess_f);

  icf::IterationCallback callback;
  if (update_visualizer_)
    callback = [this](const Eigen::Isometry3f& T, int) {
      PointCloudSource moved;
      pcl::transformPointCloud(*input_, moved, T.matrix());
      const pcl::Indices none;
      update_visualizer_(moved, none, *target_, none);
    };
  result_ = icf::estimatePose(*model_, points, camera, params, use_guess ? &guess_iso : nullptr,
                              callback);
  nr_iterations_ = result_.refinement_iterations;
  final_transformation_ = transformation_ = result_.scene_to_model.template cast<Scalar>();
  previous_transformation_ = final_transformation_;
  converged_ = result_.accepted();
  pcl::transformPointCloud(output, output, final_transformation_);
}

}  // namespace pcl
