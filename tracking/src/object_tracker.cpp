/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/global_search.h>
#include <pcl/icf/registration/rigid_transform.h>
#include <pcl/icf/registration/usable_point.h>
#include <pcl/icf/tracking/object_tracker.h>
#include <pcl/point_types.h>
#include <pcl_icf_internal/grown_model_box.h>
#include <pcl_icf_internal/parameter_check.h>
#include <pcl_icf_internal/scene_view.h>
#include <pcl_icf_internal/track_steps.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {
namespace tracking {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/** The usable points of \a view that are neither the table's nor marked in \a skip (when
 * given) inside \a model's bounding box at \a model_to_camera grown by \a margin on every
 * side (internal::GrownModelBox). */
std::vector<Eigen::Vector3f> pointsInGrownBox(const internal::SceneView& view,
                                              const std::vector<bool>& table,
                                              const std::vector<char>* skip, const IcfModel& model,
                                              const Eigen::Isometry3f& model_to_camera,
                                              float margin) {
  const internal::GrownModelBox box(model, model_to_camera, margin);
  std::vector<Eigen::Vector3f> inside;
  for (std::size_t i = 0; i < view.points.size(); ++i) {
    const Eigen::Vector3f& p = view.points[i];
    if (!table[i] && !(skip && (*skip)[i] != 0) && isUsablePoint(p) && box.contains(p))
      inside.push_back(p);
  }
  return inside;
}

}  // namespace

/** The localizer's view of the frame (points, colours, image size), moved into the camera's
 * frame. */
struct ObjectTracker::FrameView : internal::SceneView {
  Eigen::Isometry3f camera_to_scene = Eigen::Isometry3f::Identity();
};

std::string toString(TrackState state) {
  switch (state) {
    case TrackState::Searching:
      return "searching";
    case TrackState::Found:
      return "found";
    case TrackState::Tracking:
      return "tracking";
    case TrackState::Lost:
      return "lost";
    case TrackState::Refound:
      return "re-found";
  }
  return "unknown";
}

void TrackerTuning::validate() const {
  const internal::ParameterCheck fail("tracking::TrackerTuning");
  refinement.validate();
  if (!(crop_margin >= 0.f) || !std::isfinite(crop_margin))
    fail("crop_margin", crop_margin, "must be finite and >= 0");
  if (!(table_distance >= 0.f) || !std::isfinite(table_distance))
    fail("table_distance", table_distance, "must be finite and >= 0");
  if (!(velocity_gain >= 0.f && velocity_gain <= 1.f))
    fail("velocity_gain", velocity_gain, "must lie in [0, 1]");
  if (!(reacquire_margin >= 0.f) || !std::isfinite(reacquire_margin))
    fail("reacquire_margin", reacquire_margin, "must be finite and >= 0");
  if (reacquire_frames < 0)
    fail("reacquire_frames", reacquire_frames, "must be >= 0");
  if (!(reacquire_shift >= 0.f && reacquire_shift <= 1.f))
    fail("reacquire_shift", reacquire_shift, "must lie in [0, 1]");
  if (!(reacquire_full_evidence > 0.0 && reacquire_full_evidence <= 1.0))
    fail("reacquire_full_evidence", reacquire_full_evidence, "must lie in (0, 1]");
}

void TrackerParams::validate() const {
  const internal::ParameterCheck fail("tracking::TrackerParams");
  localizer.validate();
  tuning_.validate();
  if (search_interval < 1)
    fail("search_interval", search_interval, "must be >= 1");
}

ObjectTracker::ObjectTracker(const TrackerParams& params) : params_(params) {
  params_.validate();
}

int ObjectTracker::addObject(IcfModel::ConstPtr model, const std::string& name) {
  if (!model)
    throw std::invalid_argument("[pcl::icf::tracking::ObjectTracker::addObject] the model of \"" +
                                name + "\" is null");
  Object o;
  o.model = std::move(model);
  o.name = name;
  objects_.push_back(std::move(o));
  return static_cast<int>(objects_.size()) - 1;
}

void ObjectTracker::setPose(int object, const Eigen::Isometry3f& model_to_camera) {
  if (object < 0 || object >= static_cast<int>(objects_.size()))
    throw std::out_of_range("[pcl::icf::tracking::ObjectTracker::setPose] no object " +
                            std::to_string(object));
  validateRigidTransform(model_to_camera.matrix().cast<double>(),
                         "[pcl::icf::tracking::ObjectTracker::setPose] the pose");
  Object& o = objects_[static_cast<std::size_t>(object)];
  o.last = model_to_camera;
  o.last_seen = model_to_camera;
  o.previous.reset();
  o.ever_found = true;
  o.frames_lost = 0;
}

void ObjectTracker::reset() {
  for (Object& o : objects_) {
    o.ever_found = false;
    o.last.reset();
    o.previous.reset();
    o.last_seen.reset();
    o.frames_lost = 0;
  }
  plane_.reset();
  hull_.clear();
  intrinsics_.reset();
  frame_ = 0;
}

/** The depth image of the frame (camera frame), intrinsics fitted once per image size as the
 * localizer does (sceneDepthImage); the points within table_distance of the kept table plane
 * are background. */
DepthImage ObjectTracker::depthImage(const FrameView& view, std::vector<bool>& table) {
  const auto& lp = params_.localizer;
  if (!intrinsics_ || intrinsics_->width != view.width || intrinsics_->height != view.height ||
      view.width == 0) {
    intrinsics_ = DepthImage::sceneCamera(view.points, view.width, view.height, lp.intrinsics);
  }
  DepthImage image(view.points, *intrinsics_);
  table.assign(view.points.size(), false);
  if (plane_) {
    std::vector<int> background;
    for (std::size_t i = 0; i < view.points.size(); ++i) {
      const Eigen::Vector3f& p = view.points[i];
      if (isUsablePoint(p) &&
          std::abs(plane_->head<3>().dot(p) + (*plane_)[3]) < params_.tuning().table_distance) {
        table[i] = true;
        background.push_back(static_cast<int>(i));
      }
    }
    image.markBackground(view.points, background);
    if (hull_.size() >= 3)
      image.setSupportPlane(*plane_, hull_);
  }
  if (!view.colours.empty())
    image.setColours(view.points, view.colours);
  return image;
}

/** One tracking step: the pose predicted by constant velocity, refined on the points near it
 * (not the table's), verified against the depth image. */
bool ObjectTracker::refine(const FrameView& view, const DepthImage& image,
                           const std::vector<bool>& table, Object& object, ObjectTrack& out) const {
  const auto start = Clock::now();
  Eigen::Isometry3f predicted = *object.last;
  if (params_.tuning().velocity_gain > 0.f && object.previous) {
    // The last motion of the model's box centre and its turn about it, times velocity_gain.
    const Eigen::Vector3f centre =
        0.5f * (object.model->mesh().boundsMin() + object.model->mesh().boundsMax());
    const Eigen::Vector3f c_last = *object.last * centre;
    const Eigen::Vector3f c_prev = *object.previous * centre;
    Eigen::AngleAxisf turn(object.last->linear() * object.previous->linear().transpose());
    turn.angle() *= params_.tuning().velocity_gain;
    predicted.linear() = turn.toRotationMatrix() * object.last->linear();
    const Eigen::Vector3f c_pred = c_last + params_.tuning().velocity_gain * (c_last - c_prev);
    predicted.translation() = c_pred - predicted.linear() * centre;
  }
  // The points near the prediction (its box grown by crop_margin).
  const std::vector<Eigen::Vector3f> near = pointsInGrownBox(
      view, table, nullptr, *object.model, predicted, params_.tuning().crop_margin);
  out.refined = true;
  out.refine_points = static_cast<int>(near.size());
  if (near.size() < 10) {
    out.message = "too few points near the predicted pose (" + std::to_string(near.size()) + ")";
    out.refine_message = out.message;
    out.refine_ms = msSince(start);
    return false;
  }
  // One thread: the objects are refined in parallel (track).
  const RefinementResult r =
      refinePose(object.model->index(), near, predicted.inverse(), params_.tuning().refinement, 1);
  out.refine_iterations = r.iterations;
  out.refine_ms = msSince(start);
  const auto verify_start = Clock::now();
  const Eigen::Isometry3f pose = r.scene_to_model.inverse();
  out.verification =
      explainDepth(*object.model, pose, image, params_.localizer.verificationParams());
  out.confidence = out.verification.confidence;
  out.refine_confidence = out.confidence;
  out.verify_ms = msSince(verify_start);
  if (out.confidence < params_.localizer.min_confidence) {
    out.message =
        "the refined pose: " + describeRefusal(out.verification, params_.localizer.min_confidence,
                                               params_.localizer.verificationParams());
    out.refine_message = out.message;
    return false;
  }
  object.previous = object.last;
  object.last = pose;
  out.message.clear();
  return true;
}

namespace {

/** The registration starts (scene -> model) of \a hypotheses, each followed by its copies
 * moved by +-shift x the model's bounding-box extent along each of the box's three axes (the
 * model slid along them): where most of an object is hidden, the search places the model on
 * the centroid of what shows, and the right pose lies towards the hidden side, beyond the
 * refinement's reach (doc/experiments/2026-11-28-tracking-reacquisition.md, "Re-acquisition near
 * the last pose"). shift 0: the hypotheses alone. */
std::vector<Eigen::Isometry3f> startsWithShifts(const std::vector<PoseHypothesis>& hypotheses,
                                                const IcfModel& model, float shift) {
  std::vector<Eigen::Isometry3f> starts;
  const Eigen::Vector3f extent = model.mesh().boundsMax() - model.mesh().boundsMin();
  for (const PoseHypothesis& h : hypotheses) {
    starts.push_back(h.scene_to_model);
    if (shift <= 0.f)
      continue;
    for (int axis = 0; axis < 3; ++axis)
      for (const float sign : {-1.f, 1.f}) {
        // Moving the model by d in its own frame moves scene -> model by -d.
        Eigen::Isometry3f moved = h.scene_to_model;
        moved.pretranslate(-sign * shift * extent[axis] * Eigen::Vector3f::Unit(axis));
        starts.push_back(moved);
      }
  }
  return starts;
}

}  // namespace

/** Re-acquisition (TrackerParams::reacquire_margin): the points inside the model's bounding
 * box at its last accepted pose, grown by reacquire_margin, that are neither the table's nor
 * explained by the other objects' poses, searched without a guess (globalSearch, as for one
 * cluster); each distinct hypothesis is refined (refinePose) and verified against the depth
 * image (explainDepth, as a refinement's pose), and the most confident is accepted at
 * min_confidence. It skips the whole-scene search's segmentation and its search of every other
 * segment: an object put back near where it left is found in tens of milliseconds instead of
 * hundreds (doc/BENCHMARKS.md, Tracking). */
bool ObjectTracker::reacquire(const FrameView& view, const DepthImage& image,
                              const std::vector<bool>& table, const std::vector<int>& explained,
                              Object& object, ObjectTrack& out) const {
  const auto start = Clock::now();
  out.reacquire_tried = true;
  std::vector<char> skip(view.points.size(), 0);
  for (const int i : explained)
    skip[static_cast<std::size_t>(i)] = 1;
  const std::vector<Eigen::Vector3f> near = pointsInGrownBox(
      view, table, &skip, *object.model, *object.last_seen, params_.tuning().reacquire_margin);
  out.reacquire_points = static_cast<int>(near.size());
  if (near.size() < 10) {
    out.message =
        "re-acquisition: too few points near the last pose (" + std::to_string(near.size()) + ")";
    out.reacquire_ms = msSince(start);
    return false;
  }
  // The depth image as the search's: the other objects' points are explained background, so
  // a neighbour touching the object does not read as its silhouette carrying on.
  DepthImage marked = image;
  marked.markExplained(view.points, explained);
  const auto& lp = params_.localizer;
  const int threads = lp.threads > 0 ? lp.threads : omp_get_num_procs();
  // Every distinct hypothesis of the global search is refined and verified, not only the one
  // the search ranks first: on a third of a box, a pose slid along its seen face fits the
  // points as well as the right one, and only the depth image (what it would see through)
  // tells them apart.
  const std::vector<Eigen::Isometry3f> starts =
      startsWithShifts(globalSearch(*object.model, near, Eigen::Vector3f::Zero(),
                                    lp.tuning().icf.tuning().global, lp.seed, threads),
                       *object.model, params_.tuning().reacquire_shift);
  const int n = static_cast<int>(starts.size());
  DepthVerificationParams verification = lp.verificationParams();
  verification.full_evidence = params_.tuning().reacquire_full_evidence;
  std::vector<Eigen::Isometry3f> poses(starts.size());
  std::vector<DepthExplanation> explanations(starts.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (n > 1)
  for (int h = 0; h < n; ++h) {
    const std::size_t i = static_cast<std::size_t>(h);
    const RefinementResult r =
        refinePose(object.model->index(), near, starts[i], params_.tuning().refinement, 1);
    poses[i] = r.scene_to_model.inverse(Eigen::Isometry);
    explanations[i] = explainDepth(*object.model, poses[i], marked, verification);
  }
  out.reacquire_ms = msSince(start);
  if (starts.empty()) {
    out.message = "re-acquisition: the search near the last pose gave no hypothesis";
    return false;
  }
  // The most confident; the search's order breaks ties (it is deterministic).
  std::size_t best = 0;
  for (std::size_t i = 1; i < explanations.size(); ++i)
    if (explanations[i].confidence > explanations[best].confidence)
      best = i;
  out.verification = explanations[best];
  out.confidence = out.verification.confidence;
  if (out.confidence < lp.min_confidence) {
    out.message =
        "re-acquisition near the last pose, the best of " + std::to_string(n) +
        " hypotheses: " + describeRefusal(out.verification, lp.min_confidence, verification);
    return false;
  }
  const Eigen::Isometry3f pose = poses[best];
  out.reacquired = true;
  object.previous.reset();
  object.last = pose;
  out.message.clear();
  return true;
}

template <typename PointT>
bool ObjectTracker::search(const pcl::PointCloud<PointT>& frame, const FrameView& view,
                           Object& object, const std::vector<int>& explained, ObjectTrack& out) {
  const auto start = Clock::now();
  out.searched = true;
  localization::LocalizerParams params = params_.localizer;
  params.explained_indices = explained;
  const localization::Localization loc = localization::localizeObject(frame, *object.model, params);
  out.search_ms = msSince(start);
  const Eigen::Isometry3f scene_to_camera = view.camera_to_scene.inverse(Eigen::Isometry);
  if (loc.segmentation.plane.found()) {
    const Eigen::Vector4f& s = loc.segmentation.plane.coefficients;
    Eigen::Vector4f c;
    c.head<3>() = view.camera_to_scene.linear().transpose() * s.head<3>();
    c[3] = s.head<3>().dot(view.camera_to_scene.translation()) + s[3];
    plane_ = c;
    hull_.clear();
    for (const auto& vertex : loc.segmentation.hull)
      hull_.push_back(scene_to_camera * vertex);
  }
  if (loc.best < 0) {
    out.message = loc.message.empty() ? localization::toString(loc.status) : loc.message;
    return false;
  }
  const auto& best = loc.clusters[static_cast<std::size_t>(loc.best)];
  out.verification = best.verification;
  out.confidence = best.verification.confidence;
  object.previous.reset();
  object.last = scene_to_camera * best.icf.object_pose;
  out.message.clear();
  return true;
}

/** The frame's points that the other objects' poses of this frame explain (pointsExplainedBy):
 * those refined this frame, and those before \a k in order whose search has succeeded. The
 * search for object \a k treats them as background, so a tracked neighbour touching it does
 * not read as its surface carrying on past its silhouette. */
std::vector<int> ObjectTracker::explainedByOthers(const FrameView& view, DepthImage& image,
                                                  std::vector<bool>& table, std::size_t k,
                                                  const std::vector<char>& refined_ok) {
  std::vector<int> explained;
  for (std::size_t j = 0; j < objects_.size(); ++j) {
    const Object& other = objects_[j];
    const bool posed = j < k ? other.last.has_value() : (j > k && refined_ok[j] != 0);
    if (!posed)
      continue;
    if (image.empty())
      image = depthImage(view, table);
    const std::vector<int> mine = pointsExplainedBy(*other.model, *other.last, image, view.points,
                                                    params_.localizer.verificationParams());
    explained.insert(explained.end(), mine.begin(), mine.end());
  }
  std::sort(explained.begin(), explained.end());
  explained.erase(std::unique(explained.begin(), explained.end()), explained.end());
  return explained;
}

template <typename PointT>
TrackedFrame ObjectTracker::track(const pcl::PointCloud<PointT>& frame) {
  const auto start = Clock::now();
  TrackedFrame result;
  result.index = frame_++;
  FrameView view;
  static_cast<internal::SceneView&>(view) = internal::makeSceneView(frame);
  view.camera_to_scene = localization::cameraPoseOf(frame, params_.localizer);
  validateRigidTransform(view.camera_to_scene.matrix().cast<double>(),
                         "[pcl::icf::tracking::ObjectTracker::track] the camera pose");
  const Eigen::Isometry3f scene_to_camera = view.camera_to_scene.inverse(Eigen::Isometry);
  if (!scene_to_camera.matrix().isIdentity(0.f))
    for (Eigen::Vector3f& p : view.points)
      p = scene_to_camera * p;

  const bool any_tracked = std::any_of(objects_.begin(), objects_.end(),
                                       [](const Object& o) { return o.last.has_value(); });
  std::vector<bool> table;
  DepthImage image;
  if (any_tracked) {
    const auto image_start = Clock::now();
    image = depthImage(view, table);
    result.image_ms = msSince(image_start);
  }

  // The refinements first, one object per thread (each reads the shared frame and image and
  // writes its own slot: the result does not depend on the thread count); then, in order, the
  // searches, which run in parallel inside.
  const int n = static_cast<int>(objects_.size());
  std::vector<ObjectTrack> outs(objects_.size());
  std::vector<char> refined_ok(objects_.size(), 0);
  const int threads =
      params_.localizer.threads > 0 ? params_.localizer.threads : omp_get_num_procs();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (n > 1)
  for (int k = 0; k < n; ++k) {
    Object& object = objects_[static_cast<std::size_t>(k)];
    outs[static_cast<std::size_t>(k)].name = object.name;
    if (object.last)
      refined_ok[static_cast<std::size_t>(k)] =
          refine(view, image, table, object, outs[static_cast<std::size_t>(k)]) ? 1 : 0;
  }
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    Object& object = objects_[k];
    ObjectTrack& out = outs[k];
    const bool refined = refined_ok[k] != 0;
    // The rules (what to try, where the object stands after) are internal::planRecovery and
    // internal::stepTrack; this loop runs the attempts they ask for.
    const internal::TrackMemory before{out.refined, object.last_seen.has_value(), object.ever_found,
                                       object.frames_lost};
    bool recovered = false;
    const internal::RecoveryPlan plan =
        refined ? internal::RecoveryPlan{}
                : internal::planRecovery(before, params_.search_interval,
                                         params_.tuning().reacquire_frames);
    if (plan.reacquire || plan.search) {
      const std::vector<int> explained = explainedByOthers(view, image, table, k, refined_ok);
      if (plan.reacquire) {
        if (image.empty())
          image = depthImage(view, table);
        recovered = reacquire(view, image, table, explained, object, out);
      }
      if (!recovered && plan.search)
        recovered = search(frame, view, object, explained, out);
    }
    const internal::TrackStep step = internal::stepTrack(before, refined, recovered);
    out.state = step.state;
    object.ever_found = step.after.ever_found;
    object.frames_lost = step.after.frames_lost;
    if (step.after.has_pose) {
      object.last_seen = object.last;
      out.pose = view.camera_to_scene * *object.last;
    } else {
      object.last.reset();
      object.previous.reset();
    }
    out.frames_lost = object.frames_lost;
  }
  result.objects = std::move(outs);
  result.total_ms = msSince(start);
  return result;
}

template TrackedFrame ObjectTracker::track<pcl::PointXYZ>(const pcl::PointCloud<pcl::PointXYZ>&);
template TrackedFrame ObjectTracker::track<pcl::PointXYZRGB>(
    const pcl::PointCloud<pcl::PointXYZRGB>&);
template TrackedFrame ObjectTracker::track<pcl::PointXYZRGBA>(
    const pcl::PointCloud<pcl::PointXYZRGBA>&);

}  // namespace tracking
}  // namespace icf
}  // namespace pcl
