/**
 * \file synthetic_clutter.h
 * \brief A cluttered desk seen by a simulated Kinect v1 (the development data of the clutter
 * suites): 10-25 objects touching one another, some standing on a box, more on a shelf behind the
 * desk's edge, the target 30-100% visible, depth noise, holes and flying pixels along the edges;
 * and the same frame with the target taken away (its target-absent twin).
 *
 * Used by `pcl_icf_make_dataset --kind clutter` and its tests. Lengths in metres; the desk
 * frame is makeTabletopScene's table frame (z up, surface z = 0), see depth_camera.h.
 */
#pragma once

#include "synthetic/depth_camera.h"
#include "synthetic/synthetic_models.h"

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace icf {
namespace synthetic {

/** \brief How a cluttered desk is drawn. */
struct ClutterSpec {
  int min_objects = 10;  ///< objects on the desk, the target included (uniform in [min, max])
  int max_objects = 25;
  /** Each object after the first is placed against one already there (bounding circles
   * 0-gap_max apart) with this probability, else anywhere free on the desk. */
  double touch_probability = 0.6;
  double gap_max = 0.01;
  /** An object stands on the top of a box already on the desk with this probability (one
   * object per box; the target too: a can put on its neighbour). */
  double stack_probability = 0.15;
  int min_background = 2;  ///< objects on the shelf behind the desk (uniform in [min, max])
  int max_background = 5;
  /** The scene is drawn again (at most 5000 times) until the target's visible share of its
   * part inside the image (ClutterScene::target_visible) lies in [min_target_visible,
   * max_target_visible]. A target partly beyond the image's border is less visible than that
   * (ClutterScene::wholeTargetVisible). */
  double min_target_visible = 0.3;
  double max_target_visible = 1.0;
  double camera_min_height = 0.5, camera_max_height = 0.8;  ///< above the desk
  double camera_min_tilt = 35.0, camera_max_tilt = 60.0;    ///< degrees below the horizontal
  ScanNoise noise;                                          ///< seed drawn per scene
  EdgeArtefacts edges;                                      ///< seed drawn per scene
};

/** \brief One object of a desk: its model and where it stands, in the desk frame. */
struct DeskObject {
  const SyntheticModel* model = nullptr;
  double x = 0.0, y = 0.0;  ///< its footprint's centre on the surface it stands on (metres)
  double yaw = 0.0;         ///< about the desk's z (radians)
  double base = 0.0;        ///< height of that surface: 0 the desk, a box's top, the shelf
  bool stacked = false;     ///< standing on a box
  bool background = false;  ///< on the shelf behind the desk
};

/** \brief The camera above a desk and the seeds of its frame's noise. */
struct DeskView {
  double camera_height = 0.65;  ///< above the desk (metres)
  double camera_tilt = 45.0;    ///< degrees below the horizontal
  ScanNoise noise;
  EdgeArtefacts edges;
};

/** \brief One cluttered frame and its twin without the target. */
struct ClutterScene {
  Scan present;  ///< labels: 0 desk, -2 shelf, i + 1 for objects[i], -1 nothing hit
  Scan absent;   ///< the same frame (same noise) with objects[0], the target, taken away
  std::vector<std::string> names;        ///< model name per object; names[0] is the target's
  std::vector<Eigen::Isometry3d> poses;  ///< model -> camera per object (metres)
  std::vector<bool> stacked;             ///< per object: standing on a box, not on the desk
  std::vector<bool> background;          ///< per object: on the shelf behind the desk
  /** visibleShare of the target in present: of its pixels inside the image, the share seen.
   * The draw is repeated until this lies in the spec's range. */
  double target_visible = 0.0;
  /** inViewShare of the target: the share of it inside the image. A target partly beyond the
   * border is partly unseen: target_visible x target_in_view is the share of the whole target
   * seen (wholeTargetVisible), what the suite's visibility bands count. */
  double target_in_view = 1.0;
  double wholeTargetVisible() const { return target_visible * target_in_view; }
  Eigen::Vector4f desk_plane = Eigen::Vector4f::Zero();  ///< as TabletopScene::table_plane
  std::vector<DeskObject>
      layout;     ///< what was drawn (layout[0] the target): renderClutterDesk's input
  DeskView view;  ///< with layout, all renderClutterDesk needs for this scene
};

/** \brief Draws a cluttered desk around \a target from \a distractors (drawn with repetition;
 * pass none that looks like the target if a second copy must not confuse the scoring).
 * Same arguments, same scene.
 * \throws std::invalid_argument for an empty distractor list or a spec out of range;
 * std::runtime_error when 5000 draws miss the visibility range. */
ClutterScene makeClutterScene(const SyntheticModel& target,
                              const std::vector<SyntheticModel>& distractors, std::uint64_t seed,
                              const ClutterSpec& spec = {},
                              const CameraIntrinsics& intrinsics = {});

/** \brief The frame of a desk laid out by hand (\a layout[0] is the target), rendered as
 * makeClutterScene renders the layouts it draws: a test's desk written as numbers does not
 * depend on the floating-point rounding of the draws. target_visible is measured, not required.
 * \throws std::invalid_argument for an empty layout or an object without a model. */
ClutterScene renderClutterDesk(const std::vector<DeskObject>& layout, const DeskView& view,
                               const CameraIntrinsics& intrinsics = {});

}  // namespace synthetic
}  // namespace icf
}  // namespace pcl
