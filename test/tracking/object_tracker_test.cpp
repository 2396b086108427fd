/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// ObjectTracker: a synthetic sequence (an object moved smoothly, taken away for some
// frames and put back) and the real consecutive frames of ycbv-video0000.
#include "synthetic/depth_camera.h"
#include "synthetic/pose_error.h"
#include "synthetic/synthetic_models.h"
#include "synthetic/synthetic_sequence.h"
#include "test_paths.h"

#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/tracking/object_tracker.h>
#include <pcl/io/pcd_io.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace {

/** Sanitizer builds (CI's ASan and TSan runs on 2 cores): the real sequence starts from the
 * ground truth of its first frame instead of a 8 s search. */
bool sanitized() {
  return std::getenv("PCL_ICF_SANITIZED") != nullptr;
}

namespace synthetic = pcl::icf::synthetic;
using pcl::icf::IcfModel;
using pcl::icf::tracking::ObjectTracker;
using pcl::icf::tracking::TrackState;

/** The synthetic sequence: Box5 slides 8 mm and turns 2 degrees per frame beside a cup that
 * stands still; it is taken away in frames [kGoneFrom, kBackAt) and put back where its
 * trajectory has carried on. */
constexpr int kFrames = 14;
constexpr int kGoneFrom = 5;
constexpr int kBackAt = 8;

/** That sequence (the cup first, then the box), frame f's noise seeded with noise_seed + f. */
synthetic::SequenceSpec movingBoxSequence(std::uint64_t noise_seed) {
  synthetic::SequenceSpec spec;
  spec.frames = kFrames;
  spec.noise.outlier_ratio = 0.0;  // as the localizer's table-top tests (object_localizer_test)
  spec.noise.seed = noise_seed;
  synthetic::SequenceObject cup, box;
  cup.model = synthetic::thesisModel("Cup");
  cup.start = Eigen::Vector3d(0.15, -0.05, 0.0);
  box.model = synthetic::thesisModel("Box5");
  box.start = Eigen::Vector3d(-0.08, 0.02, 0.3);
  box.velocity = Eigen::Vector3d(0.008, 0.003, 2.0 * M_PI / 180.0);
  box.absent_from = kGoneFrom;
  box.absent_until = kBackAt;
  spec.objects = {cup, box};
  return spec;
}

TEST(ObjectTracker, SyntheticSequenceMovedRemovedAndPutBack) {
  const synthetic::SequenceSpec spec = movingBoxSequence(100);
  const synthetic::SyntheticModel& cup = spec.objects[0].model;
  const synthetic::SyntheticModel& box = spec.objects[1].model;
  pcl::icf::tracking::TrackerParams params;
  params.localizer.threads = 1;
  ObjectTracker tracker(params);
  tracker.addObject(IcfModel::build(box.mesh), "Box5");
  tracker.addObject(IcfModel::build(cup.mesh), "Cup");

  int lost_at = -1, refound_at = -1;
  for (int f = 0; f < kFrames; ++f) {
    const synthetic::SequenceFrame frame = synthetic::renderSequenceFrame(spec, f);
    const bool present = frame.present[1];
    EXPECT_EQ(present, f < kGoneFrom || f >= kBackAt);
    const auto out = tracker.track(*frame.scene.scan.cloud);
    ASSERT_EQ(out.objects.size(), 2u);
    const auto& b = out.objects[0];
    const auto& c = out.objects[1];
    for (const auto& o : out.objects)
      std::printf("frame %d %s %s confidence %.3f, refinement %.1f ms, search %.1f ms\n", f,
                  o.name.c_str(), toString(o.state).c_str(), o.confidence, o.refine_ms,
                  o.search_ms);
    SCOPED_TRACE("frame " + std::to_string(f) + ": box " + toString(b.state) + " (" + b.message +
                 "), cup " + toString(c.state));
    // The cup never moves: found, then tracked.
    ASSERT_TRUE(c.pose.has_value());
    EXPECT_EQ(c.state, f == 0 ? TrackState::Found : TrackState::Tracking);
    const auto cup_error = synthetic::poseError(Eigen::Isometry3d(c.pose->matrix().cast<double>()),
                                                frame.poses[0], cup.symmetry);
    EXPECT_LE(cup_error.translation, 0.01);
    EXPECT_LE(cup_error.rotation_deg, 5.0);
    if (present) {
      ASSERT_TRUE(b.pose.has_value());
      const auto error = synthetic::poseError(Eigen::Isometry3d(b.pose->matrix().cast<double>()),
                                              frame.poses[1], box.symmetry);
      std::printf("frame %d Box5 error %.1f mm %.2f deg\n", f, 1e3 * error.translation,
                  error.rotation_deg);
      EXPECT_LE(error.translation, 0.01);
      EXPECT_LE(error.rotation_deg, 5.0);
      if (f < kGoneFrom) {
        EXPECT_EQ(b.state, f == 0 ? TrackState::Found : TrackState::Tracking);
      }
      if (f >= kBackAt && refound_at < 0) {
        EXPECT_EQ(b.state, TrackState::Refound);
        refound_at = f;
      }
    } else {
      EXPECT_FALSE(b.pose.has_value()) << "a pose while the box is absent";
      EXPECT_EQ(b.state, TrackState::Lost);
      if (lost_at < 0)
        lost_at = f;
    }
  }
  EXPECT_GE(lost_at, kGoneFrom);
  EXPECT_LT(lost_at, kGoneFrom + 3) << "the loss detected within 3 frames";
  EXPECT_GE(refound_at, kBackAt);
  EXPECT_LT(refound_at, kBackAt + 5) << "re-found within 5 frames";
}

// Deterministic: two trackers, one on one thread and one on every core (the two objects refined
// in parallel), fed the same frames report the same poses, bit for bit.
TEST(ObjectTracker, SameFramesSamePoses) {
  const synthetic::SyntheticModel box = synthetic::thesisModel("Box5");
  const synthetic::SyntheticModel cup = synthetic::thesisModel("Cup");
  const IcfModel::ConstPtr model = IcfModel::build(box.mesh);
  const IcfModel::ConstPtr cup_model = IcfModel::build(cup.mesh);
  pcl::icf::tracking::TrackerParams one, all;
  one.localizer.threads = 1;
  all.localizer.threads = 0;
  ObjectTracker a(one), b(all);
  a.addObject(model, "Box5");
  b.addObject(model, "Box5");
  a.addObject(cup_model, "Cup");  // two objects: refined in parallel by b
  b.addObject(cup_model, "Cup");
  const synthetic::SequenceSpec spec = movingBoxSequence(200);
  for (int f = 0; f < 3; ++f) {
    const synthetic::TabletopScene scene = synthetic::renderSequenceFrame(spec, f).scene;
    const auto oa = a.track(*scene.scan.cloud).objects;
    const auto ob = b.track(*scene.scan.cloud).objects;
    for (std::size_t k = 0; k < 2; ++k) {
      ASSERT_TRUE(oa[k].pose && ob[k].pose) << "frame " << f << " object " << k;
      EXPECT_EQ(oa[k].pose->matrix(), ob[k].pose->matrix()) << "frame " << f << " object " << k;
    }
  }
}

// Re-acquisition (TrackerParams::reacquire_margin): with the whole-scene search held off
// (search_interval 1000: a lost object is searched only in the frame its refinement fails),
// the box put back 3.4 cm and 8 degrees from where it left is found again on the points near
// its last pose alone, in its first frame back, against the sequence's ground truth (1 cm / 5
// degrees, the bar); no pose while it is away, though re-acquisition runs in every
// one of those frames. The same tracker without re-acquisition stays lost (the control: it is
// what finds the box), and the poses are the same on one thread and on all.
TEST(ObjectTracker, ReacquiresNearItsLastPoseWithoutASearch) {
  const synthetic::SequenceSpec spec = movingBoxSequence(300);
  const synthetic::SyntheticModel& box = spec.objects[1].model;
  const IcfModel::ConstPtr box_model = IcfModel::build(box.mesh);
  const IcfModel::ConstPtr cup_model = IcfModel::build(spec.objects[0].model.mesh);
  pcl::icf::tracking::TrackerParams params;
  params.search_interval = 1000;
  params.localizer.threads = 1;
  pcl::icf::tracking::TrackerParams all_threads = params, without = params;
  all_threads.localizer.threads = 0;
  without.tuning().reacquire_frames = 0;
  ObjectTracker one(params), all(all_threads), control(without);
  for (ObjectTracker* t : {&one, &all, &control}) {
    t->addObject(box_model, "Box5");
    t->addObject(cup_model, "Cup");
  }
  for (int f = 0; f <= kBackAt; ++f) {
    const synthetic::SequenceFrame frame = synthetic::renderSequenceFrame(spec, f);
    const auto b = one.track(*frame.scene.scan.cloud).objects[0];
    const auto b_all = all.track(*frame.scene.scan.cloud).objects[0];
    const auto b_control = control.track(*frame.scene.scan.cloud).objects[0];
    SCOPED_TRACE("frame " + std::to_string(f) + ": " + toString(b.state) + " (" + b.message + ")");
    ASSERT_EQ(b.pose.has_value(), b_all.pose.has_value());
    if (b.pose) {
      EXPECT_EQ(b.pose->matrix(), b_all.pose->matrix());
    }
    if (f < kGoneFrom) {
      ASSERT_TRUE(b.pose.has_value());
      EXPECT_FALSE(b.reacquire_tried);
    } else if (f < kBackAt) {
      EXPECT_FALSE(b.pose.has_value()) << "a pose while the box is absent";
      EXPECT_TRUE(b.reacquire_tried);
      EXPECT_EQ(b.searched, f == kGoneFrom) << "searched only when its refinement failed";
    } else {
      EXPECT_EQ(b.state, TrackState::Refound);
      EXPECT_TRUE(b.reacquired);
      EXPECT_FALSE(b.searched);
      ASSERT_TRUE(b.pose.has_value());
      const auto error = synthetic::poseError(Eigen::Isometry3d(b.pose->matrix().cast<double>()),
                                              frame.poses[1], box.symmetry);
      std::printf(
          "re-acquired in frame %d: %.1f mm, %.2f deg, confidence %.3f, %d points, "
          "%.1f ms\n",
          f, 1e3 * error.translation, error.rotation_deg, b.confidence, b.reacquire_points,
          b.reacquire_ms);
      EXPECT_LE(error.translation, 0.01);
      EXPECT_LE(error.rotation_deg, 5.0);
      EXPECT_FALSE(b_control.pose.has_value()) << "the control found it without re-acquisition";
      EXPECT_FALSE(b_control.reacquire_tried);
    }
  }
}

/** pcl_icf_make_dataset --kind sequence --seed 1515's fourth sequence (seq_003; its
 * drawSequence(40, 1518), written out): Box5 moves along the back of the table, is taken away
 * in frames [15, 20) and put back behind EisKaffe, 28% visible, 25-38% in frames 20-24. */
synthetic::SequenceSpec boxBackBehindACan() {
  synthetic::SequenceSpec spec;
  spec.frames = 25;
  spec.noise.seed = 13107831760686378976ULL;
  synthetic::SequenceObject box, can, occluder;
  box.model = synthetic::thesisModel("Box5");
  box.start = Eigen::Vector3d(-0.16487154523540803, 0.14328036910590489, 1.6046704219201944);
  box.velocity = Eigen::Vector3d(0.0082435772617704024, 0.0, -0.020290247491984627);
  box.sway = Eigen::Vector3d(0.0, 0.011450550324354648, 0.0);
  box.sway_period = 28.855895156768675;
  box.absent_from = 15;
  box.absent_until = 20;
  can.model = synthetic::thesisModel("EisKaffe");
  can.start = Eigen::Vector3d(0.015096807570992105, -0.033204907274717199, 2.0078285812995631);
  can.velocity = Eigen::Vector3d(-0.00066482596629187493, 0.0, 0.0057550058713514126);
  occluder.model = synthetic::suiteModel("TallCylinder");
  occluder.tracked = false;
  occluder.start = Eigen::Vector3d(-0.27885120860742685, -0.17095012110349142, 0.0);
  occluder.velocity = Eigen::Vector3d(0.014032574842629073, 0.0, 0.0);
  spec.objects = {box, can, occluder};
  return spec;
}

// A box put back mostly hidden (TrackerParams::reacquire_shift, reacquire_full_evidence): on
// a third of a box the search places the model on the centroid of what shows, and the pose it
// refines to slides along the box's seen top face (13.9 mm off in frame 24, with the
// calibrated 0.4 share). Started also from the hypotheses moved by half the box's extent along
// its axes and accepted at 35% of full evidence, re-acquisition finds the right pose within 5
// frames of the return and gives no pose off by more than 1 cm / 5 degrees (the bar,
// against the sequence's ground truth) in any frame; none while the box is away. The control,
// re-acquisition as before both, has no right pose in frames 20-23 (it is what finds it).
TEST(ObjectTracker, ReacquiresABoxPutBackMostlyHidden) {
  const synthetic::SequenceSpec spec = boxBackBehindACan();
  const synthetic::SyntheticModel& box = spec.objects[0].model;
  const IcfModel::ConstPtr box_model = IcfModel::build(box.mesh);
  const IcfModel::ConstPtr can_model = IcfModel::build(spec.objects[1].model.mesh);
  pcl::icf::tracking::TrackerParams params, before;
  params.localizer.threads = 0;
  before = params;
  before.tuning().reacquire_shift = 0.f;
  before.tuning().reacquire_full_evidence = 0.4;
  ObjectTracker tracker(params), control(before);
  for (ObjectTracker* t : {&tracker, &control}) {
    t->addObject(box_model, "Box5");
    t->addObject(can_model, "EisKaffe");
  }
  int refound_at = -1;
  for (int f = 0; f < spec.frames; ++f) {
    const synthetic::SequenceFrame frame = synthetic::renderSequenceFrame(spec, f);
    const auto b = tracker.track(*frame.scene.scan.cloud).objects[0];
    const auto c = control.track(*frame.scene.scan.cloud).objects[0];
    SCOPED_TRACE("frame " + std::to_string(f) + " (visible " + std::to_string(frame.visible[0]) +
                 "): " + toString(b.state) + " (" + b.message + ")");
    if (!frame.present[0]) {
      EXPECT_FALSE(b.pose.has_value()) << "a pose while the box is absent";
      continue;
    }
    auto accurate = [&](const pcl::icf::tracking::ObjectTrack& o) {
      if (!o.pose)
        return false;
      const auto e = synthetic::poseError(Eigen::Isometry3d(o.pose->matrix().cast<double>()),
                                          frame.poses[0], box.symmetry);
      return e.translation <= 0.01 && e.rotation_deg <= 5.0;
    };
    if (b.pose) {
      EXPECT_TRUE(accurate(b)) << "a pose beyond 1 cm / 5 degrees";
    }
    if (f >= 20 && refound_at < 0 && accurate(b))
      refound_at = f;
    if (f >= 20 && f < 24) {
      EXPECT_FALSE(accurate(c)) << "the control found it";
    }
  }
  std::printf("re-found in frame %d (the box is back in frame 20)\n", refound_at);
  EXPECT_GE(refound_at, 20);
  EXPECT_LT(refound_at, 25) << "re-found within 5 frames of its return";
}

TEST(ObjectTracker, RejectsBadParameters) {
  pcl::icf::tracking::TrackerParams params;
  params.search_interval = 0;
  EXPECT_THROW(ObjectTracker{params}, std::invalid_argument);
  params.search_interval = 1;
  params.tuning().reacquire_frames = -1;
  EXPECT_THROW(ObjectTracker{params}, std::invalid_argument);
  params.tuning().reacquire_frames = 30;
  params.tuning().reacquire_margin = -0.01f;
  EXPECT_THROW(ObjectTracker{params}, std::invalid_argument);
  params.tuning().reacquire_margin = 0.1f;
  params.tuning().reacquire_shift = 1.5f;
  EXPECT_THROW(ObjectTracker{params}, std::invalid_argument);
  params.tuning().reacquire_shift = 0.5f;
  params.tuning().reacquire_full_evidence = 0.0;
  EXPECT_THROW(ObjectTracker{params}, std::invalid_argument);
  ObjectTracker tracker;
  EXPECT_THROW(tracker.addObject(nullptr, "none"), std::invalid_argument);
}

/** ycbv-video0000 frames 2-10: the gelatin box found in frame 2 and tracked, every frame within
 * 1 cm of the ground truth. */
TEST(ObjectTracker, YcbVideoFramesTwoToTen) {
  const std::string root = "ycbv-video0000/";
  PCL_ICF_REQUIRE_SHARED(readme, root + "README.md");
  const pcl::PolygonMesh mesh = pcl::icf::io::loadPolygonMesh(
      pcl_icf_test::sharedData(root + "models/ycb_009_gelatin_box.ply"));
  pcl::icf::tracking::TrackerParams params;
  params.localizer.threads = 0;  // the first frame's search on both cores (same result)
  ObjectTracker tracker(params);
  tracker.addObject(IcfModel::build(mesh), "gelatin_box");
  const int first = 2, last = sanitized() ? 4 : 10;
  for (int frame = first; frame <= last; ++frame) {
    char id[8];
    std::snprintf(id, sizeof(id), "%03d", frame);
    const std::string case_dir =
        pcl_icf_test::sharedData(root + "cases/y0000_" + id + "_gelatin_box");
    ASSERT_FALSE(case_dir.empty()) << frame;
    std::ifstream in(case_dir + "/gt.json");
    const nlohmann::json gt = nlohmann::json::parse(in);
    Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
    for (const auto& o : gt["objects"])
      if (o.value("target", false))
        for (int r = 0; r < 4; ++r)
          for (int k = 0; k < 4; ++k)
            truth.matrix()(r, k) = o["pose"][r][k].get<double>();
    pcl::PointCloud<pcl::PointXYZRGB> scene;
    ASSERT_EQ(pcl::io::loadPCDFile(
                  pcl_icf_test::sharedData(root + "scenes/ycbv0000_000" + id + ".pcd"), scene),
              0);
    if (frame == first && sanitized())
      tracker.setPose(0, truth.cast<float>());
    const auto out = tracker.track(scene);
    const auto& t = out.objects.front();
    SCOPED_TRACE("frame " + std::to_string(frame) + ": " + toString(t.state) + " " + t.message);
    ASSERT_TRUE(t.pose.has_value());
    EXPECT_EQ(t.state, frame == first && !sanitized() ? TrackState::Found : TrackState::Tracking);
    const Eigen::Vector3d offset = t.pose->translation().cast<double>() - truth.translation();
    std::printf(
        "frame %d %s confidence %.3f, refinement %.1f ms, verification %.1f ms, search "
        "%.0f ms, depth image %.1f ms, error %.1f mm\n",
        frame, toString(t.state).c_str(), t.confidence, t.refine_ms, t.verify_ms, t.search_ms,
        out.image_ms, 1e3 * offset.norm());
    EXPECT_LE(offset.norm(), 0.01);
  }
}

}  // namespace
