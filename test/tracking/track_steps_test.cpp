/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// The tracker's state machine without frames (pcl_icf_internal/track_steps.h): the expected
// attempts and states are the rules TrackerParams and TrackState document, written out by hand
// frame by frame.
#include <pcl_icf_internal/track_steps.h>

#include <gtest/gtest.h>

#include <vector>

namespace {

using pcl::icf::internal::planRecovery;
using pcl::icf::internal::RecoveryPlan;
using pcl::icf::internal::stepTrack;
using pcl::icf::internal::TrackMemory;
using pcl::icf::internal::TrackStep;
using pcl::icf::tracking::TrackState;

TrackMemory tracked() {
  TrackMemory m;
  m.has_pose = true;
  m.seen_before = true;
  m.ever_found = true;
  return m;
}

TEST(TrackSteps, AVerifiedRefinementIsTrackingAndResetsTheLoss) {
  const TrackStep step = stepTrack(tracked(), /*refined=*/true, /*recovered=*/false);
  EXPECT_EQ(step.state, TrackState::Tracking);
  EXPECT_TRUE(step.after.has_pose);
  EXPECT_TRUE(step.after.seen_before);
  EXPECT_EQ(step.after.frames_lost, 0);
}

TEST(TrackSteps, FoundTheFirstTimeRefoundAfter) {
  const TrackMemory never;  // never found: no pose, nothing seen
  const TrackStep first = stepTrack(never, false, true);
  EXPECT_EQ(first.state, TrackState::Found);
  EXPECT_TRUE(first.after.ever_found);
  EXPECT_TRUE(first.after.has_pose);
  EXPECT_TRUE(first.after.seen_before);

  TrackMemory lost = first.after;
  lost.has_pose = false;
  lost.frames_lost = 4;
  const TrackStep again = stepTrack(lost, false, true);
  EXPECT_EQ(again.state, TrackState::Refound);
  EXPECT_EQ(again.after.frames_lost, 0);
  // A failed refinement recovered in the same frame (re-acquisition or search) is Refound too.
  EXPECT_EQ(stepTrack(tracked(), false, true).state, TrackState::Refound);
}

TEST(TrackSteps, NeitherIsSearchingOrLostAndCountsTheFrame) {
  const TrackStep searching = stepTrack(TrackMemory{}, false, false);
  EXPECT_EQ(searching.state, TrackState::Searching);
  EXPECT_FALSE(searching.after.ever_found);
  EXPECT_EQ(searching.after.frames_lost, 1);

  const TrackStep lost = stepTrack(tracked(), false, false);
  EXPECT_EQ(lost.state, TrackState::Lost);
  EXPECT_FALSE(lost.after.has_pose);
  EXPECT_TRUE(lost.after.seen_before) << "a loss keeps the last-seen pose for re-acquisition";
  EXPECT_TRUE(lost.after.ever_found);
  EXPECT_EQ(lost.after.frames_lost, 1);
  EXPECT_EQ(stepTrack(lost.after, false, false).after.frames_lost, 2);
}

TEST(TrackSteps, AFailedRefinementReacquiresAndSearchesAtOnce) {
  // Whatever the intervals: the object was there a frame ago.
  for (int interval : {1, 3, 7})
    for (int window : {1, 30}) {
      const RecoveryPlan plan = planRecovery(tracked(), interval, window);
      EXPECT_TRUE(plan.reacquire) << interval << " " << window;
      EXPECT_TRUE(plan.search) << interval << " " << window;
    }
  // Re-acquisition off (reacquire_frames 0): straight to the search.
  const RecoveryPlan off = planRecovery(tracked(), 3, 0);
  EXPECT_FALSE(off.reacquire);
  EXPECT_TRUE(off.search);
}

TEST(TrackSteps, ALostObjectIsReacquiredInItsWindowAndSearchedEveryIntervalFrames) {
  // search_interval 3, reacquire_frames 2; tracked until frame 0, lost from frame 1 on.
  const std::vector<RecoveryPlan> expected = {
      {true, true},    // frame 1: the refinement failed: both at once
      {true, false},   // frames_lost 1: in the window (1 < 2), 1 % 3 != 0
      {false, false},  // frames_lost 2: out of the window, 2 % 3 != 0
      {false, true},   // frames_lost 3: searched
      {false, false},  // 4
      {false, false},  // 5
      {false, true},   // 6
  };
  TrackMemory memory = tracked();
  for (std::size_t frame = 0; frame < expected.size(); ++frame) {
    const RecoveryPlan plan = planRecovery(memory, 3, 2);
    EXPECT_EQ(plan.reacquire, expected[frame].reacquire) << "frame " << frame + 1;
    EXPECT_EQ(plan.search, expected[frame].search) << "frame " << frame + 1;
    memory = stepTrack(memory, false, false).after;
    EXPECT_EQ(memory.frames_lost, static_cast<int>(frame) + 1);
  }
}

TEST(TrackSteps, ANeverFoundObjectIsSearchedOnlyNeverReacquired) {
  // Nothing seen, so nothing to look near; search_interval 2: frames_lost 0, 2, 4 searched.
  TrackMemory memory;
  for (int frame = 0; frame < 6; ++frame) {
    const RecoveryPlan plan = planRecovery(memory, 2, 30);
    EXPECT_FALSE(plan.reacquire) << "frame " << frame;
    EXPECT_EQ(plan.search, frame % 2 == 0) << "frame " << frame;
    const TrackStep step = stepTrack(memory, false, false);
    EXPECT_EQ(step.state, TrackState::Searching);
    memory = step.after;
  }
}

}  // namespace
