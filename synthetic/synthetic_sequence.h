/**
 * \file synthetic_sequence.h
 * \brief A synthetic stream of table-top frames with ground truth: objects moved along smooth
 * trajectories, taken away and put back, hiding one another (the tracking tests' data).
 *
 * Used by the tracker's test and by `pcl_icf_make_dataset --kind sequence`. Frames are
 * rendered with makeTabletopScene (same table, camera and noise model); lengths in metres,
 * angles in radians, positions on the table frame (z up, surface z = 0, see depth_camera.h).
 */
#pragma once

#include "synthetic/depth_camera.h"
#include "synthetic/synthetic_models.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace pcl {
namespace icf {
namespace synthetic {

/** \brief One object of a sequence and where it stands, frame by frame. */
struct SequenceObject {
  SyntheticModel model;
  /** (x, y, yaw) on the table at frame 0 (metres, metres, radians). */
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  /** (x, y, yaw) added per frame: a steady motion. */
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  /** Amplitude of a sinusoidal (x, y, yaw) offset of period sway_period frames added to the
   * steady motion (0 or a period <= 0: none), so that the path curves smoothly. */
  Eigen::Vector3d sway = Eigen::Vector3d::Zero();
  double sway_period = 0.0;
  /** Taken off the table in frames [absent_from, absent_until) (-1: never); it is put back
   * where its trajectory has carried on. */
  int absent_from = -1;
  int absent_until = -1;
  /** False for a distractor or an occluder nobody follows (the ground truth still lists it). */
  bool tracked = true;

  /** \brief (x, y, yaw) on the table in \a frame. */
  Eigen::Vector3d placement(int frame) const;
  /** \brief Whether it stands on the table in \a frame. */
  bool present(int frame) const;
};

/** \brief A sequence: its objects, length, camera and noise. */
struct SequenceSpec {
  std::vector<SequenceObject> objects;
  int frames = 0;
  CameraIntrinsics intrinsics;
  /** Frame f is rendered with noise.seed + f. */
  ScanNoise noise;
  double camera_height = 0.6;     ///< metres above the table (makeTabletopScene)
  double camera_tilt_deg = 45.0;  ///< below the horizontal (makeTabletopScene)
};

/** \brief One rendered frame and its ground truth. */
struct SequenceFrame {
  /** The objects present, in the spec's order (scene.poses and labels follow that subset). */
  TabletopScene scene;
  /** Per spec object: whether it is on the table. */
  std::vector<bool> present;
  /** Per spec object: model -> camera (metres); where it would stand when absent. */
  std::vector<Eigen::Isometry3d> poses;
  /** Per spec object: the share of the whole object seen, visibleShare x inViewShare (its
   * pixels in the frame over the pixels it covers rendered alone, without noise, in an image
   * wide enough to hold all of it): 1 unhidden and in view, 0 absent, wholly hidden or out of
   * view; a part beyond the frame's border is unseen. */
  std::vector<double> visible;
};

/** \brief Renders frame \a frame of \a spec. Same spec and frame, same output.
 * \throws std::invalid_argument for a frame outside [0, spec.frames) or what
 * makeTabletopScene refuses. */
SequenceFrame renderSequenceFrame(const SequenceSpec& spec, int frame);

}  // namespace synthetic
}  // namespace icf
}  // namespace pcl
