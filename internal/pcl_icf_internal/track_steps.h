/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Internal to tracking (not installed): ObjectTracker's state machine for one object
 * and one frame, as pure functions of what the object carries from the frame before and of what
 * this frame's attempts gave. ObjectTracker::track runs the attempts (refinement,
 * re-acquisition, search: the frame's work) and asks these what to try and where the object
 * stands after; the unit tests check the rules without frames. */

#include <pcl/icf/tracking/object_tracker.h>

namespace pcl {
namespace icf {
namespace internal {

/** \brief What the state machine knows of one tracked object between two frames. */
struct TrackMemory {
  bool has_pose = false;     ///< a pose accepted in the frame before: it is refined from
  bool seen_before = false;  ///< a pose accepted in some frame: re-acquisition looks near it
  bool ever_found = false;   ///< some frame (or setPose) gave a pose
  int frames_lost = 0;       ///< frames since the last accepted pose (0 while tracked)
};

/** \brief What a frame tries after the object's refinement failed (or when it had no pose to
 * refine from). */
struct RecoveryPlan {
  bool reacquire = false;  ///< the search near the last-seen pose, first
  bool search = false;     ///< the search of the whole scene, when re-acquisition did not find it
};

/** \brief The recovery for an object whose refinement failed this frame or that had no pose
 * (TrackerParams::search_interval >= 1, reacquire_frames >= 0, as validate() checks): a failed
 * refinement (before.has_pose) re-acquires, when the object was seen and re-acquisition is on,
 * then searches, in the same frame; an object lost for frames_lost frames is re-acquired while
 * frames_lost < reacquire_frames and searched when frames_lost is a multiple of
 * search_interval. */
inline RecoveryPlan planRecovery(const TrackMemory& before, int search_interval,
                                 int reacquire_frames) {
  RecoveryPlan plan;
  plan.search = before.has_pose || before.frames_lost % search_interval == 0;
  plan.reacquire = before.seen_before && reacquire_frames > 0 &&
                   (before.has_pose || before.frames_lost < reacquire_frames);
  return plan;
}

/** \brief Where the object stands after a frame, and what it carries to the next. */
struct TrackStep {
  tracking::TrackState state = tracking::TrackState::Searching;
  TrackMemory after;
};

/** \brief The frame's outcome: refined (the refinement from the last pose was verified) gives
 * Tracking; otherwise recovered (a re-acquisition or a search was verified) gives Found the
 * first time and Refound after; neither gives Lost, or Searching while the object was never
 * found, and one more frame lost. A pose accepted this frame is the next frame's pose and its
 * last-seen pose; a loss drops the pose and keeps the last-seen one. */
inline TrackStep stepTrack(const TrackMemory& before, bool refined, bool recovered) {
  TrackStep step;
  step.after = before;
  if (refined || recovered) {
    step.state = refined             ? tracking::TrackState::Tracking
                 : before.ever_found ? tracking::TrackState::Refound
                                     : tracking::TrackState::Found;
    step.after.has_pose = true;
    step.after.seen_before = true;
    step.after.ever_found = true;
    step.after.frames_lost = 0;
  } else {
    step.state = before.ever_found ? tracking::TrackState::Lost : tracking::TrackState::Searching;
    step.after.has_pose = false;
    ++step.after.frames_lost;
  }
  return step;
}

}  // namespace internal
}  // namespace icf
}  // namespace pcl
