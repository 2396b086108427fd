/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The average distance pose errors beside BOP's: ADD and ADD-S (Hinterstoisser et al.,
 * ACCV 2012; the BOP toolkit's pose_error.add and adi), and ADD-S to the model's surface, the
 * one pcl_icf's suites score with (doc/DATASETS.md, the scoring rule). A pose maps model
 * coordinates to camera coordinates; lengths in any one unit, the errors come out in it. */

#include <pcl/icf/registration/icf_model.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace pcl {
namespace icf {
namespace evaluation {

/** \brief ADD: the mean over the model's \a points x of |est x - gt x|.
 * \throws std::invalid_argument for no points. */
double add(const Eigen::Isometry3d& est, const Eigen::Isometry3d& gt,
           const std::vector<Eigen::Vector3d>& points);

/** \brief ADD-S (the BOP toolkit's adi): the mean over the model's \a points x of the distance
 * from gt x to the nearest of the points posed by \a est (a k-d tree, pcl::KdTreeFLANN).
 * \throws std::invalid_argument for no points. */
double adi(const Eigen::Isometry3d& est, const Eigen::Isometry3d& gt,
           const std::vector<Eigen::Vector3d>& points);

/** \brief ADD-S to the surface: the mean over \a points x (model frame, metres as \a model) of
 * the exact distance from gt x to the surface of \a model posed by \a est (its face index). Any
 * pose that maps the surface onto itself scores 0, with no floor set by the points' spacing.
 * \throws std::invalid_argument for no points. */
double addSToSurface(const IcfModel& model, const Eigen::Isometry3d& est,
                     const Eigen::Isometry3d& gt, const std::vector<Eigen::Vector3d>& points);

}  // namespace evaluation
}  // namespace icf
}  // namespace pcl
