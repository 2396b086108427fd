/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Following known objects over a stream of depth frames: the first frame, or
 * the first after a loss, is searched with the scene-level localizer (localizeObject); every
 * next frame refines the last pose, moved on by a constant-velocity prediction, with iterative
 * closest face (refinePose) on the points near the prediction, and verifies it with the same
 * depth verification and confidence as a single frame (explainDepth, accepted at
 * LocalizerParams::min_confidence). A refinement that fails the verification falls back, in the
 * same frame, first to a re-acquisition near where the object was last seen (the global search
 * of iterative closest face on the points around its last pose: an object put back, or moved
 * fast, is usually near where it was), then to a search of the whole scene;
 * while an object stays lost it is searched again every search_interval frames. */

#include <pcl/icf/localization/object_localizer.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/refinement.h>
#include <pcl/icf/verification/depth_image.h>
#include <pcl/icf/verification/depth_verification.h>
#include <pcl/point_cloud.h>

#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <vector>

namespace pcl {
namespace icf {
namespace tracking {

/** \brief Where an object stands after a frame. */
enum class TrackState {
  Searching,  ///< not found yet: every search so far failed (no pose)
  Found,      ///< found for the first time by a search this frame
  Tracking,   ///< refined from the last pose and verified
  Lost,       ///< was found before, neither the refinement nor a search verified it (no pose)
  Refound,    ///< found again after a loss, or after a failed refinement: by a re-acquisition
              ///< near its last pose (ObjectTrack::reacquired) or by a search
};
/** "searching", "found", "tracking", "lost", "re-found". */
std::string toString(TrackState state);

/** \brief The tracker's calibration constants (doc/TUNING.md), reached through
 * TrackerParams::tuning(): a user leaves them as they are. Lengths in metres. */
struct TrackerTuning {
  /** RefinementParams' defaults, at most 800 points per iteration (an evenly strided subset:
   * a real 640 x 480 frame holds 17-25k points of a box at 0.6 m; 800 keep ycbv-video0000's
   * gelatin box within 0.5 mm of the ground truth, as 1500 and all of them do, in 5 ms
   * instead of 9 and 90). */
  static RefinementParams defaultRefinement() {
    RefinementParams r;
    r.max_points = 800;
    return r;
  }

  /** The per-frame refinement from the predicted pose. Its first Tukey radius bounds how far
   * the object may move beyond the constant-velocity prediction between two frames. */
  RefinementParams refinement = defaultRefinement();
  /** The refinement sees the points within the model's bounding box (at the predicted pose)
   * grown by this on every side. */
  float crop_margin = 0.02f;
  /** Points within this height of the table (kept from the last search) are not refined
   * against and are the verification's background. */
  float table_distance = 0.01f;
  /** The next pose is predicted from the last two (constant velocity): the last motion of the
   * model's bounding-box centre and its turn about it, times this gain. 1: the full constant
   * velocity; 0: the last pose. Below 1, an error the refinement cannot see (the turn of a
   * can about its axis, a box sliding along its own face) stays bounded instead of growing
   * frame by frame; 0.5 lags a steady motion by half a frame's move, well within the
   * refinement's first radius. */
  float velocity_gain = 0.5f;
  /** Re-acquisition: an object whose refinement failed, or lost for at most reacquire_frames
   * frames, is first searched on the points within the model's bounding box at its last
   * accepted pose grown by reacquire_margin on every side, leaving out the table and the
   * points the other objects' poses explain (the global search without a guess, each
   * hypothesis refined and verified as a tracked pose is, accepted at min_confidence). Only
   * when that fails is the whole scene searched: a crop costs a fraction of a whole-scene
   * search. The margin bounds how far the object may have moved while
   * lost: 0.1 m is 3 mm a frame for a second at 30 Hz, or a hand's move of a few
   * centimetres and back. */
  float reacquire_margin = 0.1f;
  /** Frames after a loss during which re-acquisition is tried (0: never; then a failed
   * refinement goes straight to the search). */
  int reacquire_frames = 30;
  /** Re-acquisition also starts the refinement from each hypothesis moved by +-reacquire_shift
   * x the model's bounding-box extent along each box axis (0: the hypotheses alone): an object
   * put back is often mostly hidden, and on the third of it that shows the search's pose
   * slides along the seen face, beyond the refinement's reach. */
  float reacquire_shift = 0.5f;
  /** The share of a re-acquired pose's rendered pixels that must be supported for full
   * evidence (DepthVerificationParams::full_evidence, the search's) among the starts shifted
   * along the box axes, which can slide a pose along a seen face (calibration: doc/TUNING.md,
   * "The tracker"). */
  double reacquire_full_evidence = 0.35;

  /** \throws std::invalid_argument naming the field and value. */

  /** \throws std::invalid_argument naming the field. */
  void validate() const;
};

/** \brief Parameters of ObjectTracker: its localizer's (the search and the verification) and
 * how often a lost object is searched; the rest is tuning(). Lengths in metres. */
struct TrackerParams {
  /** The search (first frame, after a loss) and the verification: its tuning().verification,
   * min_confidence, camera_pose, intrinsics and threads are used by the tracking step too. */
  localization::LocalizerParams localizer;
  /** A lost object is searched in every n-th frame only (1: every frame): the search costs
   * 10-100x a refinement, this bounds its share of the stream's time. */
  int search_interval = 1;

  TrackerTuning& tuning() { return tuning_; }
  const TrackerTuning& tuning() const { return tuning_; }

  /** \throws std::invalid_argument naming the field. */
  void validate() const;

 private:
  TrackerTuning tuning_;
};

/** \brief One object after one frame. */
struct ObjectTrack {
  std::string name;
  TrackState state = TrackState::Searching;
  /** Model -> scene (the frame's coordinates); set in Found, Tracking and Refound only. */
  std::optional<Eigen::Isometry3f> pose;
  /** The verification's confidence of the pose tried last (0 when none was tried). */
  double confidence = 0.0;
  DepthExplanation verification;  ///< of the pose tried last
  bool refined = false;           ///< a refinement was tried this frame
  /** The refined pose's confidence (when refined), and why it was not accepted ("" when it
   * was): a search that follows replaces confidence and message. */
  double refine_confidence = 0.0;
  std::string refine_message;
  bool searched = false;  ///< a search ran this frame
  int refine_points = 0;  ///< points near the prediction
  int refine_iterations = 0;
  double refine_ms = 0.0;  ///< the crop and the refinement (iterative closest face)
  double verify_ms = 0.0;  ///< the refined pose's verification (explainDepth)
  double search_ms = 0.0;
  bool reacquire_tried = false;  ///< a re-acquisition near the last pose ran this frame
  bool reacquired = false;       ///< and its pose was accepted (state Refound, no search)
  int reacquire_points = 0;      ///< the points it searched
  double reacquire_ms = 0.0;     ///< its search, refinement and verification
  int frames_lost = 0;           ///< consecutive frames without a pose since it was last seen
  std::string message;           ///< why the pose was not accepted ("" when it was)
};

/** \brief One frame's outcome. */
struct TrackedFrame {
  int index = 0;                     ///< 0-based count of frames given to track()
  std::vector<ObjectTrack> objects;  ///< in the order of addObject
  double image_ms = 0.0;             ///< the depth image built once per frame
  double total_ms = 0.0;
};

/** \brief Follows objects over consecutive frames of one static camera.
 *
 * Frames must come in order from the same camera (the table plane and the intrinsics are
 * kept between frames; a frame of another size fits them again). Deterministic: the same
 * frames give the same poses (the search is seeded by localizer.seed, the refinement
 * reduces in a fixed order). The objects are refined in parallel, one per thread
 * (localizer.threads; 0: all cores), each into its own slot, so the result does not depend on
 * the thread count; searches run one object after another, each in parallel inside. The
 * tracker itself is not thread-safe; the models are shared, not copied, and must
 * outlive the tracker.
 * \code
 * pcl::icf::tracking::ObjectTracker tracker;
 * tracker.addObject(pcl::icf::IcfModel::build(mesh), "box");
 * for (const auto& frame : frames) {
 *   const auto out = tracker.track(*frame);
 *   if (out.objects[0].pose) use(*out.objects[0].pose);
 * }
 * \endcode */
class ObjectTracker {
 public:
  /** \throws std::invalid_argument for invalid parameters. */
  explicit ObjectTracker(const TrackerParams& params = {});

  /** \brief Adds an object to follow; returns its index in TrackedFrame::objects.
   * \throws std::invalid_argument for a null model. */
  int addObject(IcfModel::ConstPtr model, const std::string& name);

  /** \brief Starts object \a object from \a model_to_camera (a pose from elsewhere, in the
   * camera's frame) instead of a search; the next frame refines from it.
   * \throws std::out_of_range for a bad index, std::invalid_argument for a pose that is not a
   * rigid motion. */
  void setPose(int object, const Eigen::Isometry3f& model_to_camera);

  /** \brief Tracks every object in \a frame (metres; camera pose as for localizeObject). */
  template <typename PointT>
  TrackedFrame track(const pcl::PointCloud<PointT>& frame);

  /** \brief Forgets every pose (the next frame searches everything again). */
  void reset();

  const TrackerParams& params() const { return params_; }
  std::size_t size() const { return objects_.size(); }

 private:
  struct Object {
    IcfModel::ConstPtr model;
    std::string name;
    bool ever_found = false;
    std::optional<Eigen::Isometry3f> last;      ///< model -> camera, last accepted
    std::optional<Eigen::Isometry3f> previous;  ///< the one before, in the frame before
    /** The last accepted pose, kept through a loss (re-acquisition looks near it). */
    std::optional<Eigen::Isometry3f> last_seen;
    int frames_lost = 0;
  };
  /** The frame in the camera's frame, as the refinement and verification need it. */
  struct FrameView;

  template <typename PointT>
  bool search(const pcl::PointCloud<PointT>& frame, const FrameView& view, Object& object,
              const std::vector<int>& explained, ObjectTrack& out);
  std::vector<int> explainedByOthers(const FrameView& view, DepthImage& image,
                                     std::vector<bool>& table, std::size_t k,
                                     const std::vector<char>& refined_ok);
  bool refine(const FrameView& view, const DepthImage& image, const std::vector<bool>& table,
              Object& object, ObjectTrack& out) const;
  bool reacquire(const FrameView& view, const DepthImage& image, const std::vector<bool>& table,
                 const std::vector<int>& explained, Object& object, ObjectTrack& out) const;
  DepthImage depthImage(const FrameView& view, std::vector<bool>& table);

  TrackerParams params_;
  std::vector<Object> objects_;
  std::optional<Eigen::Vector4f> plane_;  ///< the table in the camera's frame
  std::vector<Eigen::Vector3f> hull_;     ///< its hull in the camera's frame (may be empty)
  std::optional<PinholeIntrinsics> intrinsics_;
  int frame_ = 0;
};

}  // namespace tracking
}  // namespace icf
}  // namespace pcl
