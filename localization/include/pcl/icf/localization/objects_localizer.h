/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Every known object in one call: the scene's work done once (its view, the table,
 * the clusters, the depth image), the hypotheses of every model ranked and judged as
 * localizeObject judges one model's, then one selection over all of them in which each scene
 * point is explained by at most one accepted pose. Where poses of two models claim the same
 * points, the better explanation (the higher score) wins and the other is refused with the
 * reason "explained better by NAME instance K". BOP's task "ViVo" (an image and a list of
 * objects with instance counts in, every pose with a score out). */

#include <pcl/icf/localization/object_localizer.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl/point_cloud.h>

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace pcl {
namespace icf {
namespace localization {

/** \brief One object asked for. */
struct ObjectQuery {
  IcfModel::ConstPtr model;  ///< prepared once (IcfModel::build); must not be null
  /** What refusals call it ("explained better by NAME instance K"); "" reads "object N", N its
   * place in the list. */
  std::string name;
  /** At most this many instances (an upper bound, as BOP's instance counts). */
  int max_instances = 1;
};

/** \brief One accepted pose of the frame: ObjectsLocalization::objects[object].clusters
 * [hypothesis]. */
struct ObjectInstance {
  int object = -1;
  int hypothesis = -1;
};

/** \brief The frame's outcome for every object asked for. */
struct ObjectsLocalization {
  /** Scene-wide: BadScene or NoClusters when the scene itself cannot be searched (then every
   * object has that status too), Found when any object was, else NotFound. */
  LocalizationStatus status = LocalizationStatus::NotFound;
  std::string message;
  /** One per query, in order, as localizeObject returns it: that object's judged hypotheses,
   * its accepted instances after the selection, its status and message; its segmentation is
   * the frame's (below). Its total_ms is the frame's shared work plus its own search. */
  std::vector<Localization> objects;
  /** Every accepted instance of every object, best score first (ties: the lower object, then
   * the lower hypothesis). */
  std::vector<ObjectInstance> instances;
  segmentation::TabletopSegmentation segmentation;
  Eigen::Isometry3f camera_pose = Eigen::Isometry3f::Identity();  ///< camera -> scene
  /** The scene's work done once (segmentation, depth image), the selection's, and all. */
  double scene_ms = 0.0, selection_ms = 0.0, total_ms = 0.0;
};

/** \brief Finds every object of \a objects in \a scene in one pass (see the file's comment).
 * \a params apply to every object, except max_instances (each query's own) and the colour
 * cue, which describes one object: it must be unset when more than one is asked for.
 * localizeObject is the one-object case of the same code. Deterministic for params.seed;
 * independent of params.threads.
 * \throws std::invalid_argument for invalid parameters, an empty list or a null model; bad
 * data gives a status. */
template <typename PointT>
ObjectsLocalization localizeObjects(const pcl::PointCloud<PointT>& scene,
                                    const std::vector<ObjectQuery>& objects,
                                    const LocalizerParams& params = {});

/** \brief The instances of a frame: over every object's accepted hypotheses by score (ties: the
 * lower object, then the lower hypothesis), each kept when at most \a max_shared of its
 * explained points are explained by a kept one too and its object has fewer than its
 * \a max_instances. An accepted hypothesis that loses its points to another object's instance
 * is refused (accepted false, reason "explained better by NAME instance K", NAME from
 * \a names); one that loses them to its own object's is that instance found twice and stays
 * as it is. Returns every object's kept hypotheses, best first. */
std::vector<std::vector<int>> selectInstances(std::vector<Localization>& objects,
                                              const std::vector<int>& max_instances,
                                              const std::vector<std::string>& names,
                                              double max_shared);

}  // namespace localization
}  // namespace icf
}  // namespace pcl

// localizeObjects is compiled into pcl_icf_localization for PCL_ICF_SEGMENTATION_POINT_TYPES
// (its body is in src/impl/object_localizer.hpp, not installed).
