// The pieces of the fast global search (pcl_icf_internal/search_anchors.h; doc/icf.md
// section 4) on their own, on point sets whose answer is known by construction: the robust
// centroid of a sphere's points among far strays is the mean of the sphere's points; the
// cluster spread of points at known distances is their 90th percentile; one object gives one
// anchor on its centroid, two objects far apart give windows on both; the random subset is a
// subset, in order, the same for a seed, and draws every point equally often.
#include <pcl_icf_internal/search_anchors.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace {

using pcl::icf::GlobalSearchParams;
using pcl::icf::internal::clusterSpread;
using pcl::icf::internal::randomSubset;
using pcl::icf::internal::robustCentroid;
using pcl::icf::internal::translationAnchors;

/** \a count points uniform on a sphere of \a radius about \a centre (seeded). */
std::vector<Eigen::Vector3f> sphere(const Eigen::Vector3f& centre, float radius, int count,
                                    std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> n;
  std::vector<Eigen::Vector3f> out;
  for (int i = 0; i < count; ++i)
    out.push_back(centre + radius * Eigen::Vector3f(n(rng), n(rng), n(rng)).normalized());
  return out;
}

Eigen::Vector3f mean(const std::vector<Eigen::Vector3f>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : points)
    sum += p.cast<double>();
  return (sum / static_cast<double>(points.size())).cast<float>();
}

TEST(RobustCentroid, IgnoresFarStraysAndKeepsTheObject) {
  // 2000 points of a 5 cm sphere 1 m in front of the camera, and 20 strays 1e5 m away (a plain
  // mean moves by 1000 m). Every sphere point lies within 1.5 x the 90th-percentile distance of
  // the median (all lie at about the radius), every stray far beyond: the robust centroid is
  // the mean of the sphere's points. Tolerance 1e-6 m: both are sums of the same points in
  // double, in the same order, rounded to float once (float spacing at 1 m is 6e-8 m).
  const Eigen::Vector3f centre(0.1f, -0.05f, 1.0f);
  const auto object = sphere(centre, 0.05f, 2000, 5);
  auto points = object;
  for (int i = 0; i < 20; ++i)
    points.insert(points.begin() + 97 * i, Eigen::Vector3f(1e5f, 1e5f * (i % 2), -1e5f));
  const Eigen::Vector3f robust = robustCentroid(points);
  EXPECT_LE((robust - mean(object)).norm(), 1e-6f);
  EXPECT_GT((mean(points) - mean(object)).norm(), 100.f);  // what the strays do to a mean
  // Without strays: the plain mean, and near the sphere's centre (the 2000 directions average
  // out to about radius / sqrt(2000) = 1 mm).
  EXPECT_LE((robustCentroid(object) - mean(object)).norm(), 1e-6f);
  EXPECT_LE((robustCentroid(object) - centre).norm(), 0.005f);
}

TEST(ClusterSpread, IsThe90thPercentileDistance) {
  // 100 points at distances 1, 2, ..., 100 mm from the centroid along random directions: the
  // 90th percentile, the distance of sorted rank 100 x 9 / 10 = 90 (0-based), is 91 mm. Float
  // rounding of the points (at 0.8 m, 6e-8 m) moves it by about 1e-7 m: tolerance 1e-6 m.
  std::mt19937_64 rng(6);
  std::normal_distribution<float> n;
  const Eigen::Vector3f c(0.2f, 0.1f, 0.8f);
  std::vector<Eigen::Vector3f> points;
  for (int k = 100; k >= 1; --k)
    points.push_back(c + 0.001f * k * Eigen::Vector3f(n(rng), n(rng), n(rng)).normalized());
  const std::size_t rank = points.size() * 9 / 10;  // the index the header's percentile takes
  EXPECT_NEAR(clusterSpread(points, c), 0.001f * static_cast<float>(rank + 1), 1e-6f);
  EXPECT_EQ(clusterSpread({}, c), 0.f);
}

TEST(TranslationAnchors, OneObjectOneAnchorOnItsCentroid) {
  // A sphere as wide as the model: not wider than merged_cluster_ratio x the model radius, so
  // the search places the model on the robust centroid, scored on a seeded subsample.
  const GlobalSearchParams params;
  const auto points = sphere(Eigen::Vector3f(0.f, 0.f, 0.9f), 0.05f, 1500, 7);
  const auto anchors = translationAnchors(points, 0.05f, params, 3);
  ASSERT_EQ(anchors.size(), 1u);
  EXPECT_EQ(anchors[0].centre, robustCentroid(points));
  EXPECT_EQ(anchors[0].subset, randomSubset(points, params.subsample, 3));
}

TEST(TranslationAnchors, TwoObjectsFarApartGetWindowsOnBoth) {
  // Two model-sized spheres 40 cm apart in one cluster (a Euclidean cluster that merged them):
  // the spread exceeds 1.2 x the model radius, so the search runs in windows. Each window holds
  // the points within the model radius of its cell, so every window lies on one sphere, and
  // each sphere gets windows whose centre is inside it (within its radius of its centre).
  const GlobalSearchParams params;
  const float radius = 0.05f;
  const Eigen::Vector3f a(-0.2f, 0.f, 1.f), b(0.2f, 0.f, 1.f);
  auto points = sphere(a, radius, 4000, 8);
  const auto other = sphere(b, radius, 4000, 9);
  points.insert(points.end(), other.begin(), other.end());
  const auto anchors = translationAnchors(points, radius, params, 4);
  ASSERT_GT(anchors.size(), 1u);
  EXPECT_LE(anchors.size(), params.max_anchors);
  int on_a = 0, on_b = 0;
  for (const auto& anchor : anchors) {
    ASSERT_FALSE(anchor.subset.empty());
    EXPECT_LE(anchor.subset.size(), params.subsample);
    const bool near_a = (anchor.centre - a).norm() < radius;
    const bool near_b = (anchor.centre - b).norm() < radius;
    EXPECT_TRUE(near_a || near_b) << anchor.centre.transpose();
    on_a += near_a;
    on_b += near_b;
    // A window's points all come from one sphere (the spheres are 30 cm apart, the window
    // is 2 model radii across).
    const Eigen::Vector3f own = near_a ? a : b;
    for (const auto& p : anchor.subset)
      ASSERT_NEAR((p - own).norm(), radius, 1e-5f);
  }
  EXPECT_GT(on_a, 0);
  EXPECT_GT(on_b, 0);
  // The same seed, the same windows.
  const auto again = translationAnchors(points, radius, params, 4);
  ASSERT_EQ(again.size(), anchors.size());
  for (std::size_t k = 0; k < anchors.size(); ++k) {
    EXPECT_EQ(again[k].centre, anchors[k].centre);
    EXPECT_EQ(again[k].subset, anchors[k].subset);
  }
}

TEST(RandomSubset, ASeededSubsetInOrder) {
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 1000; ++i)
    points.emplace_back(static_cast<float>(i), 0.f, 0.f);  // x is the point's index
  const auto subset = randomSubset(points, 256, 21);
  ASSERT_EQ(subset.size(), 256u);
  for (std::size_t k = 1; k < subset.size(); ++k)
    ASSERT_LT(subset[k - 1].x(), subset[k].x()) << "distinct points, in their original order";
  EXPECT_EQ(randomSubset(points, 256, 21), subset);
  EXPECT_NE(randomSubset(points, 256, 22), subset);
  // Fewer points than asked for: all of them, as they are.
  const std::vector<Eigen::Vector3f> few(points.begin(), points.begin() + 100);
  EXPECT_EQ(randomSubset(few, 256, 21), few);
}

TEST(RandomSubset, DrawsEveryPointEquallyOften) {
  // 10 of 50 points, 4000 seeds: each point is drawn with probability 1/5, 800 times expected,
  // standard deviation sqrt(4000 x 0.2 x 0.8) = 25. Seeded, so the counts are fixed; a bound
  // of 6 standard deviations (650 - 950) fails only for a biased draw (a modulo bias or an
  // off-by-one in the partial Fisher-Yates shifts a point's share by far more).
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 50; ++i)
    points.emplace_back(static_cast<float>(i), 0.f, 0.f);
  std::vector<int> drawn(points.size(), 0);
  for (std::uint64_t seed = 0; seed < 4000; ++seed)
    for (const auto& p : randomSubset(points, 10, seed))
      ++drawn[static_cast<std::size_t>(p.x())];
  for (std::size_t i = 0; i < drawn.size(); ++i) {
    EXPECT_GE(drawn[i], 650) << "point " << i;
    EXPECT_LE(drawn[i], 950) << "point " << i;
  }
}

}  // namespace
