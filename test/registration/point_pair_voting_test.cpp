// Point pair voting's pieces against oracles: the feature against hand-worked pairs, the
// reference frame and the angle against their defining identities, the model's table against a
// brute-force listing of every pair, and the voting end to end against the ground truth of
// simulated scans (the ray caster's, depth_camera.h) with a known pose.
#include "synthetic/depth_camera.h"
#include "synthetic/pose_error.h"
#include "synthetic/synthetic_models.h"

#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/point_pair_voting.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <tuple>

namespace {

using namespace pcl::icf;

constexpr float kPi = static_cast<float>(M_PI);

// Hand-worked: p2 one unit along x from p1; n1 along +y (perpendicular to d), n2 along +x
// (parallel to d): |d| 1, angle(n1, d) 90, angle(n2, d) 0, angle(n1, n2) 90 degrees. Float
// rounding of atan2 on unit vectors: 1e-6.
TEST(PointPairFeature, HandWorkedPairs) {
  const Eigen::Vector4f f = pointPairFeature({0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 0, 0});
  EXPECT_NEAR(f[0], 1.f, 1e-6f);
  EXPECT_NEAR(f[1], kPi / 2, 1e-6f);
  EXPECT_NEAR(f[2], 0.f, 1e-6f);
  EXPECT_NEAR(f[3], kPi / 2, 1e-6f);
  // Opposite normals, d at 45 degrees to n1: angles 45, 135, 180.
  const Eigen::Vector4f g = pointPairFeature({0, 0, 0}, {1, 0, 0}, {2, 2, 0}, {-1, 0, 0});
  EXPECT_NEAR(g[0], std::sqrt(8.f), 1e-6f);
  EXPECT_NEAR(g[1], kPi / 4, 1e-6f);
  EXPECT_NEAR(g[2], 3 * kPi / 4, 1e-6f);
  EXPECT_NEAR(g[3], kPi, 1e-6f);
}

// The frame takes its point to the origin and its normal to +x, for normals in every direction
// (the hard cases: along +-x, where FromTwoVectors meets its singular and identity ends).
TEST(PointPairFrame, TakesThePointToTheOriginAndTheNormalToX) {
  const std::vector<Eigen::Vector3f> normals = {{1, 0, 0},
                                                {-1, 0, 0},
                                                {0, 1, 0},
                                                {0, 0, -1},
                                                Eigen::Vector3f(1, 2, 3).normalized(),
                                                Eigen::Vector3f(-1, 1e-4f, 0).normalized()};
  const Eigen::Vector3f p(0.3f, -0.2f, 0.9f);
  for (const auto& n : normals) {
    const Eigen::Isometry3f frame = pointPairFrame(p, n);
    EXPECT_LT((frame * p).norm(), 1e-6f) << n.transpose();
    EXPECT_LT((frame.linear() * n - Eigen::Vector3f::UnitX()).norm(), 1e-5f) << n.transpose();
    EXPECT_NEAR(frame.linear().determinant(), 1.f, 1e-5f);
  }
}

// Drost's identity: a pair and the same pair moved by T are aligned by
// frame_s^-1 Rx(alpha_m - alpha_s) frame_m, which is T itself (up to float rounding).
TEST(PointPairAngle, AlignsAPairWithItsMovedCopy) {
  std::mt19937_64 rng(7);
  std::normal_distribution<float> g;
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3f m1(g(rng), g(rng), g(rng)), m2(g(rng), g(rng), g(rng));
    const Eigen::Vector3f n1 = Eigen::Vector3f(g(rng), g(rng), g(rng)).normalized();
    Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
    t.linear() = synthetic::randomRotation(rng).cast<float>();
    t.translation() = Eigen::Vector3f(g(rng), g(rng), g(rng));
    const Eigen::Vector3f s1 = t * m1, s2 = t * m2, ns1 = t.linear() * n1;
    const Eigen::Isometry3f fm = pointPairFrame(m1, n1), fs = pointPairFrame(s1, ns1);
    const float alpha = pointPairAngle(fm, m2) - pointPairAngle(fs, s2);
    const Eigen::Isometry3f aligned =
        fs.inverse(Eigen::Isometry) * Eigen::AngleAxisf(alpha, Eigen::Vector3f::UnitX()) * fm;
    EXPECT_LT((aligned.matrix() - t.matrix()).cwiseAbs().maxCoeff(), 2e-4f) << "trial " << trial;
  }
}

// The table against brute force: every ordered pair of the model's samples that is not of one
// plane lies in the bin of its own feature (binOf) with its angle, and the table holds nothing
// else.
TEST(PointPairModel, TablesEveryPairInItsFeaturesBin) {
  const synthetic::SyntheticModel box = synthetic::thesisModel("Box5");
  PointPairModelParams params;
  params.sampling_step = 0.15f;  // a small table, so that the brute force stays quick
  const PointPairModel m = PointPairModel::build(FaceMesh::build(box.mesh), params);
  ASSERT_FALSE(m.empty());
  const auto& p = m.points();
  const auto& n = m.normals();
  std::multiset<std::tuple<long, std::uint32_t, long>> expected, tabled;
  std::size_t coplanar = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Eigen::Isometry3f frame = pointPairFrame(p[i], n[i]);
    for (std::size_t j = 0; j < p.size(); ++j)
      if (i != j) {
        const Eigen::Vector4f f = pointPairFeature(p[i], n[i], p[j], n[j]);
        // Of one plane: both normals within coplanar_deg of each other and of perpendicular to
        // the pair (an independent restatement of the rule, in degrees).
        const float deg = 180.f / kPi;
        if (f[3] * deg < params.coplanar_deg && std::abs(f[1] * deg - 90.f) < params.coplanar_deg &&
            std::abs(f[2] * deg - 90.f) < params.coplanar_deg) {
          ++coplanar;
          continue;
        }
        const long bin = m.binOf(f);
        ASSERT_GE(bin, 0) << "a pair within the diameter is outside the table";
        expected.emplace(bin, static_cast<std::uint32_t>(i),
                         std::lround(1e5 * pointPairAngle(frame, p[j])));
      }
  }
  const long bins = static_cast<long>(m.distanceBins()) * m.featureAngleBins() *
                    m.featureAngleBins() * m.featureAngleBins();
  for (long b = 0; b < bins; ++b)
    for (const auto* e = m.binBegin(b); e != m.binEnd(b); ++e)
      tabled.emplace(b, e->reference, std::lround(1e5 * e->alpha));
  EXPECT_EQ(m.pairs() + coplanar, p.size() * (p.size() - 1));
  EXPECT_GT(coplanar, 0u);  // a box has pairs on each face
  EXPECT_TRUE(expected == tabled);
  // The samples lie on the box (its half sizes 7, 4.5, 2.5 cm) with outward normals.
  for (std::size_t i = 0; i < p.size(); ++i)
    EXPECT_GT(n[i].dot(p[i]), 0.f) << "sample " << i << " has an inward normal";
  // The diameter is the box's (16.5 cm) within two sampling steps.
  EXPECT_NEAR(m.diameter(), std::sqrt(0.14 * 0.14 + 0.09 * 0.09 + 0.05 * 0.05), 2 * m.step());
}

// A mesh wound inside out (every face reversed) gets its normals flipped back as a whole.
TEST(PointPairModel, FlipsAnInsideOutMesh) {
  pcl::PolygonMesh mesh = synthetic::thesisModel("Box5").mesh;
  for (auto& polygon : mesh.polygons)
    std::reverse(polygon.vertices.begin(), polygon.vertices.end());
  const PointPairModel m = PointPairModel::build(FaceMesh::build(mesh));
  for (std::size_t i = 0; i < m.points().size(); ++i)
    EXPECT_GT(m.normals()[i].dot(m.points()[i]), 0.f) << "sample " << i;
}

struct VotingScene {
  std::vector<Eigen::Vector3f> points;
  std::vector<int> eligible;
};

/** The simulated Kinect scan of \a objects (every hit point eligible). */
VotingScene scanOf(const std::vector<synthetic::SceneObject>& objects, std::uint64_t seed) {
  synthetic::ScanNoise noise;
  noise.seed = seed;
  const synthetic::Scan scan = synthetic::renderScan(objects, synthetic::CameraIntrinsics(), noise);
  VotingScene s;
  for (std::size_t i = 0; i < scan.cloud->size(); ++i) {
    const auto& q = (*scan.cloud)[i];
    s.points.emplace_back(q.x, q.y, q.z);
    if (std::isfinite(q.z))
      s.eligible.push_back(static_cast<int>(i));
  }
  return s;
}

// End to end on simulated Kinect scans (1.5 mm noise at 1 m, 5% outliers): the box among four
// other objects, at three poses; one of the returned hypotheses lies within the refinement's
// basin of the truth (centre within 2 sampling steps, 8 mm, rotation within 15 degrees up to
// the box's symmetry), and the same on 1 and 2 threads.
TEST(VoteForPoses, FindsABoxAmongOtherObjects) {
  const synthetic::SyntheticModel box = synthetic::thesisModel("Box5");
  const synthetic::SyntheticModel can = synthetic::thesisModel("EisKaffe");
  const synthetic::SyntheticModel prism = synthetic::thesisModel("Amicelly");
  const synthetic::SyntheticModel cup = synthetic::suiteModel("Cup");
  const IcfModel::ConstPtr model = IcfModel::build(box.mesh);
  std::mt19937_64 rng(2026);
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = synthetic::randomRotation(rng);
    pose.translation() = Eigen::Vector3d(0.02 * trial, -0.03, 0.75 + 0.1 * trial);
    std::vector<synthetic::SceneObject> objects(4);
    objects[0].mesh = &box.mesh;
    objects[0].pose = pose;
    const synthetic::SyntheticModel* others[] = {&can, &prism, &cup};
    const double xs[] = {-0.2, 0.2, -0.05};
    for (int k = 0; k < 3; ++k) {
      objects[static_cast<std::size_t>(k + 1)].mesh = &others[k]->mesh;
      objects[static_cast<std::size_t>(k + 1)].pose.translation() =
          Eigen::Vector3d(xs[k], 0.08, 0.9);
    }
    const VotingScene s = scanOf(objects, 100 + static_cast<std::uint64_t>(trial));
    const PointPairScene scene = subsampleForVoting(
        s.points, s.eligible, model->pointPairs().step(), 2 * model->pointPairs().step(), 2);
    ASSERT_GT(scene.points.size(), 100u);
    const std::vector<VotedPose> one = voteForPoses(*model, scene, {}, 1);
    const std::vector<VotedPose> two = voteForPoses(*model, scene, {}, 2);
    ASSERT_EQ(one.size(), two.size());
    for (std::size_t k = 0; k < one.size(); ++k)
      EXPECT_TRUE(one[k].model_to_camera.isApprox(two[k].model_to_camera, 0.f)) << k;
    bool found = false;
    for (const VotedPose& v : one) {
      const synthetic::PoseError e =
          synthetic::poseError(v.model_to_camera.cast<double>(), pose, box.symmetry);
      found = found || (e.translation < 2 * model->pointPairs().step() && e.rotation_deg < 15.0);
    }
    EXPECT_TRUE(found) << "trial " << trial << ": no hypothesis near the box";
  }
}

// The subsample's normals face the camera, the box alone is found first, and the pair cap
// leaves a view alone.
TEST(VoteForPoses, FindsABoxAloneFirst) {
  const synthetic::SyntheticModel box = synthetic::thesisModel("Box5");
  const IcfModel::ConstPtr model = IcfModel::build(box.mesh);
  std::vector<synthetic::SceneObject> objects(1);
  objects[0].mesh = &box.mesh;
  objects[0].pose.linear() =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  objects[0].pose.translation() = Eigen::Vector3d(0, 0, 0.8);
  const VotingScene s = scanOf(objects, 5);
  const PointPairScene scene = subsampleForVoting(s.points, s.eligible, model->pointPairs().step(),
                                                  2 * model->pointPairs().step());
  ASSERT_GT(scene.points.size(), 50u);
  for (std::size_t i = 0; i < scene.points.size(); ++i)
    EXPECT_LT(scene.normals[i].dot(scene.points[i]), 0.f) << "normal " << i << " faces away";
  const std::vector<VotedPose> voted = voteForPoses(*model, scene);
  ASSERT_FALSE(voted.empty());
  const synthetic::PoseError e = synthetic::poseError(voted.front().model_to_camera.cast<double>(),
                                                      objects[0].pose, box.symmetry);
  EXPECT_LT(e.translation, 2 * model->pointPairs().step());
  EXPECT_LT(e.rotation_deg, 15.0);

  // A camera's view of a surface holds fewer points within the model's diameter than one flat
  // disc of it on the voting grid: the pair cap at its smallest (one disc) leaves the votes
  // exactly as without a cap (a million discs).
  PointPairVotingParams one_disc, uncapped;
  one_disc.max_pairs_discs = 1.f;
  uncapped.max_pairs_discs = 1e6f;
  const std::vector<VotedPose> capped = voteForPoses(*model, scene, one_disc);
  const std::vector<VotedPose> free = voteForPoses(*model, scene, uncapped);
  ASSERT_EQ(capped.size(), free.size());
  for (std::size_t k = 0; k < free.size(); ++k)
    EXPECT_TRUE(capped[k].model_to_camera.isApprox(free[k].model_to_camera, 0.f)) << k;
}

// The box half hidden behind a board nearer the camera, beside two big boxes: with the scene's
// depth image, voteForPoses keeps its best `kept` (3) by explained samples exactly as without,
// then adds up to kept_visible more, best first by the share of what they show that the scene
// explains (each explaining at least rescore_min_share of its facing samples). Only the added
// ones reach the refinement's basin of the box's true pose (the ray caster's; the same
// tolerance as above).
TEST(VoteForPoses, AddsThePosesThatExplainWhatTheyShow) {
  const synthetic::SyntheticModel box = synthetic::thesisModel("Box5");
  const pcl::PolygonMesh board = synthetic::makeBox(0.2, 0.4, 0.01);
  const pcl::PolygonMesh big = synthetic::makeBox(0.25, 0.2, 0.15);
  const IcfModel::ConstPtr model = IcfModel::build(box.mesh);
  std::vector<synthetic::SceneObject> objects(4);
  objects[0].mesh = &box.mesh;
  objects[0].pose.linear() = (Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitX()) *
                              Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitY()))
                                 .toRotationMatrix();
  objects[0].pose.translation() = Eigen::Vector3d(0.03, -0.02, 0.8);
  objects[1].mesh = &board;
  objects[1].pose.translation() = Eigen::Vector3d(-0.1, -0.015, 0.6);
  objects[2].mesh = objects[3].mesh = &big;
  objects[2].pose.translation() = Eigen::Vector3d(-0.35, 0.05, 0.95);
  objects[3].pose.translation() = Eigen::Vector3d(0.25, 0.1, 1.0);
  synthetic::ScanNoise noise;
  noise.seed = 11;
  const synthetic::Scan scan = synthetic::renderScan(objects, synthetic::CameraIntrinsics(), noise);
  const std::vector<Eigen::Vector3f> points = synthetic::scanPoints(scan);
  std::vector<int> eligible;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (std::isfinite(points[i].z()))
      eligible.push_back(static_cast<int>(i));
  const PointPairScene scene = subsampleForVoting(points, eligible, model->pointPairs().step(),
                                                  2 * model->pointPairs().step(), 2);
  const DepthImage image(points, PinholeIntrinsics());
  PointPairVotingParams params;
  params.kept = 3;
  params.kept_visible = 10;
  const std::vector<VotedPose> alone = voteForPoses(*model, scene, params, 2);
  const std::vector<VotedPose> voted = voteForPoses(*model, scene, params, 2, &image);
  ASSERT_GE(voted.size(), alone.size());
  ASSERT_LE(voted.size(), alone.size() + params.kept_visible);
  for (std::size_t k = 0; k < alone.size(); ++k)
    EXPECT_TRUE(voted[k].model_to_camera.isApprox(alone[k].model_to_camera, 0.f)) << k;
  for (std::size_t k = alone.size(); k < voted.size(); ++k) {
    EXPECT_GE(voted[k].explained, params.rescore_min_share) << k;
    EXPECT_GE(voted[k].explained_visible, voted[k].explained) << k;
    if (k + 1 < voted.size()) {
      EXPECT_GE(voted[k].explained_visible, voted[k + 1].explained_visible) << k;
    }
  }
  const auto nearTheBox = [&](const VotedPose& v) {
    const synthetic::PoseError e =
        synthetic::poseError(v.model_to_camera.cast<double>(), objects[0].pose, box.symmetry);
    return e.translation < 2 * model->pointPairs().step() && e.rotation_deg < 15.0;
  };
  // The scene this test is about: by explained samples alone, the big boxes' faces outrank
  // every pose on the half-hidden box.
  EXPECT_FALSE(std::any_of(alone.begin(), alone.end(), nearTheBox));
  EXPECT_TRUE(std::any_of(voted.begin(), voted.end(), nearTheBox))
      << "no hypothesis near the hidden box";
}

/** \a n points: a noisy plane at 1 m facing the camera (\a volume false, 10 x 10 cm, 0.5 mm
 * noise), or uniform in a 10 cm cube there. Seeded. */
std::vector<Eigen::Vector3f> planeOrVolume(std::size_t n, bool volume, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> across(-0.05f, 0.05f);
  std::normal_distribution<float> noise(0.f, 0.0005f);
  std::vector<Eigen::Vector3f> points;
  for (std::size_t i = 0; i < n; ++i) {
    const float x = across(rng), y = across(rng);
    points.emplace_back(x, y, 1.f + (volume ? across(rng) : noise(rng)));
  }
  return points;
}

std::vector<int> allOf(const std::vector<Eigen::Vector3f>& points) {
  std::vector<int> all(points.size());
  for (std::size_t i = 0; i < all.size(); ++i)
    all[i] = static_cast<int>(i);
  return all;
}

// Against brute force: of each grid cell, the point nearest its centre (ties: the lower index);
// the same at 1 and 2 threads.
TEST(SubsampleForVoting, KeepsThePointNearestEachCellsCentre) {
  const std::vector<Eigen::Vector3f> points = planeOrVolume(20000, false, 21);
  const float step = 0.004f;
  std::map<std::tuple<long, long, long>, int> nearest;
  const auto centreDistance = [&](int i) {
    const Eigen::Vector3f& p = points[static_cast<std::size_t>(i)];
    return (p - ((p / step).array().floor() + 0.5f).matrix() * step).squaredNorm();
  };
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    const Eigen::Vector3f c = (points[static_cast<std::size_t>(i)] / step).array().floor();
    const auto key = std::make_tuple(long(c.x()), long(c.y()), long(c.z()));
    const auto it = nearest.find(key);
    if (it == nearest.end() || centreDistance(i) < centreDistance(it->second))
      nearest[key] = i;
  }
  std::set<int> expected;
  for (const auto& [key, i] : nearest)
    expected.insert(i);
  const PointPairScene one = subsampleForVoting(points, allOf(points), step, 2 * step, 1);
  const PointPairScene two = subsampleForVoting(points, allOf(points), step, 2 * step, 2);
  EXPECT_EQ(one.indices, two.indices);
  EXPECT_EQ(std::set<int>(one.indices.begin(), one.indices.end()), expected);
  EXPECT_EQ(one.step, step);
}

// A point budget: a plane is gridded coarser until it fits, near the budget (its cells fall
// as 1 / step^2), its normals still the plane's; a volume too, within the budget; the same at
// 1 and 2 threads. Without a budget the plane keeps one point per cell of the step.
TEST(SubsampleForVoting, KeepsAPointBudget) {
  const float step = 0.002f;
  const std::vector<Eigen::Vector3f> plane = planeOrVolume(40000, false, 22);
  const PointPairScene all = subsampleForVoting(plane, allOf(plane), step, 2 * step, 2);
  ASSERT_GT(all.points.size(), 2000u);  // (10 cm / 2 mm)^2 cells, nearly all hold a point
  const PointPairScene budget = subsampleForVoting(plane, allOf(plane), step, 2 * step, 2, 500);
  EXPECT_LE(budget.points.size(), 500u);
  EXPECT_GE(budget.points.size(), 250u);
  EXPECT_GT(budget.step, 2.f * step);
  // The coarser grid's normals are fitted to some 25 support points in their radius (about 12
  // at the plane's border) with 0.5 mm noise across 9 mm: within 8 degrees for 95% of them,
  // within 15 for every one.
  std::size_t within_8 = 0;
  for (std::size_t i = 0; i < budget.points.size(); ++i) {
    EXPECT_GT(std::abs(budget.normals[i].z()), std::cos(15.f * 3.14159265f / 180.f)) << i;
    within_8 += std::abs(budget.normals[i].z()) > std::cos(8.f * 3.14159265f / 180.f) ? 1 : 0;
  }
  EXPECT_GE(within_8, budget.points.size() * 95 / 100);
  // One point over the budget: the grid still coarsens (by at least 5% a round) until it fits.
  const std::size_t just_under = all.indices.size() - 1;
  const PointPairScene tight =
      subsampleForVoting(plane, allOf(plane), step, 2 * step, 2, just_under);
  EXPECT_LE(tight.indices.size(), just_under);
  EXPECT_GT(tight.step, step);
  const std::vector<Eigen::Vector3f> volume = planeOrVolume(100000, true, 23);
  const PointPairScene one = subsampleForVoting(volume, allOf(volume), step, 2 * step, 1, 2000);
  const PointPairScene two = subsampleForVoting(volume, allOf(volume), step, 2 * step, 2, 2000);
  EXPECT_LE(one.points.size(), 2000u);
  EXPECT_GT(one.points.size(), 100u);
  EXPECT_EQ(one.indices, two.indices);
  EXPECT_EQ(one.step, two.step);
}

TEST(PointPairParams, RejectsOutOfRangeFields) {
  PointPairModelParams m;
  m.angle_bins = 40;  // more than the 32 flags a word holds
  EXPECT_THROW(m.validate(), std::invalid_argument);
  PointPairVotingParams v;
  v.reference_share = 0.f;
  EXPECT_THROW(v.validate(), std::invalid_argument);
  v = {};
  v.kept = 0;
  EXPECT_THROW(v.validate(), std::invalid_argument);
  v = {};
  v.max_pairs_discs = 0.5f;  // less than one disc would thin out a camera's view
  EXPECT_THROW(v.validate(), std::invalid_argument);
  v = {};
  v.rescore_min_share = 1.5f;
  EXPECT_THROW(v.validate(), std::invalid_argument);
  v = {};
  v.rescore_hidden_distance = std::numeric_limits<float>::infinity();
  EXPECT_THROW(v.validate(), std::invalid_argument);
}

}  // namespace
