// Table-top segmentation (pcl_icf::segmentation): parameter contracts, each stage on synthetic
// scenes made in code, bad inputs (a status, never a crash), determinism, the grid clustering
// against pcl::EuclideanClusterExtraction, and real Kinect scenes from ../shared/data: the PCL
// milk scene against its reference cut milk.pcd, and four mOSD scenes against their per-point
// labels (precision/recall per object segment).
#include "test_paths.h"

#include <pcl/common/point_tests.h>
#include <pcl/icf/segmentation/convexity_split.h>
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace {

namespace seg = pcl::icf::segmentation;
using seg::TabletopStatus;

// ---------------------------------------------------------------------------------------------
// Helpers

/** Expects \a f to throw std::invalid_argument whose message contains every fragment. */
template <typename F>
void expectInvalid(F&& f, const std::vector<std::string>& fragments) {
  try {
    f();
    ADD_FAILURE() << "no std::invalid_argument thrown (expected one naming " << fragments[0] << ")";
  } catch (const std::invalid_argument& e) {
    for (const auto& fragment : fragments) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos)
          << "message \"" << e.what() << "\" lacks \"" << fragment << "\"";
    }
  }
}

template <typename PointT>
PointT makePoint(float x, float y, float z) {
  PointT p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

/** A synthetic table-top in the camera frame (x right, y down, z forward, metres): a table
 * y = 0.4 (40 cm below the camera) for x in [-0.5, 0.5], z in [0.6, 1.6], 5 mm grid, and boxes
 * standing on it, their camera-facing and top faces sampled on a 3 mm grid from 12 mm above the
 * table (12 mm: clear of the 1 cm plane threshold). Noise: uniform +-1 mm along y, from a seeded
 * generator. */
template <typename PointT>
struct SyntheticScene {
  pcl::PointCloud<PointT> cloud;
  std::vector<pcl::Indices> boxes;  ///< indices of each box's points

  explicit SyntheticScene(std::uint64_t seed = 1) : rng_(seed) {}

  void addTable() {
    for (float x = -0.5f; x <= 0.5f; x += 0.005f)
      for (float z = 0.6f; z <= 1.6f; z += 0.005f)
        cloud.push_back(makePoint<PointT>(x, kTableY + noise(), z));
    finish();
  }

  /** Box of half-widths (hx, hz) centred at (cx, cz) on the table, height h. */
  void addBox(float cx, float cz, float hx, float hz, float h) {
    pcl::Indices members;
    const auto add = [&](float x, float y, float z) {
      members.push_back(static_cast<pcl::index_t>(cloud.size()));
      cloud.push_back(makePoint<PointT>(x, y, z));
    };
    const float step = 0.003f;
    for (float x = cx - hx; x <= cx + hx; x += step)
      for (float up = 0.012f; up <= h; up += step)
        add(x, kTableY - up, cz - hz);  // front face, towards the camera
    for (float x = cx - hx; x <= cx + hx; x += step)
      for (float z = cz - hz; z <= cz + hz; z += step)
        add(x, kTableY - h, z);  // top face
    boxes.push_back(members);
    finish();
  }

  static constexpr float kTableY = 0.4f;

 private:
  float noise() { return std::uniform_real_distribution<float>(-0.001f, 0.001f)(rng_); }
  void finish() {
    cloud.width = static_cast<std::uint32_t>(cloud.size());
    cloud.height = 1;
    cloud.is_dense = true;
  }
  std::mt19937_64 rng_;
};

/** Exact-coordinate key of a point: milk.pcd was cut out of the scene, so its points are bitwise
 * scene points. */
using Key = std::tuple<float, float, float>;

template <typename PointT>
Key keyOf(const PointT& p) {
  return Key{p.x, p.y, p.z};
}

template <typename PointT>
pcl::PointCloud<PointT> loadCloud(const std::string& path) {
  pcl::PointCloud<PointT> cloud;
  if (pcl::io::loadPCDFile(path, cloud) != 0)
    ADD_FAILURE() << "cannot read " << path;
  return cloud;
}

bool sameClusters(const std::vector<pcl::PointIndices>& a,
                  const std::vector<pcl::PointIndices>& b) {
  if (a.size() != b.size())
    return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].indices != b[i].indices)
      return false;
  return true;
}

// ---------------------------------------------------------------------------------------------
// Parameters: documented defaults are the real defaults; validate() names field and value.

TEST(SegmentationParams, DocumentedDefaults) {
  const seg::VoxelParams voxel;
  EXPECT_EQ(voxel.voxel_size, 0.0);

  const seg::TablePlaneParams plane;
  EXPECT_EQ(plane.distance_threshold, 0.01);
  EXPECT_EQ(plane.max_iterations, 1000);
  EXPECT_EQ(plane.seed, 0u);
  EXPECT_EQ(plane.min_inliers, 500u);
  EXPECT_EQ(plane.probability, 0.99);
  EXPECT_TRUE(plane.refine);

  const seg::AboveTableParams above;
  EXPECT_EQ(above.min_height, 0.004);
  EXPECT_EQ(above.max_height, 0.5);

  const seg::ClusterParams cluster;
  EXPECT_EQ(cluster.tolerance, 0.02);
  EXPECT_EQ(cluster.min_size, 100u);
  EXPECT_EQ(cluster.max_size, 250000u);
  EXPECT_EQ(cluster.method, seg::ClusterMethod::Grid);

  const seg::TabletopParams all;
  EXPECT_EQ(all.voxel.voxel_size, 0.01);
  EXPECT_EQ(all.plane.distance_threshold, plane.distance_threshold);
  EXPECT_EQ(all.above_table.min_height, above.min_height);
  EXPECT_EQ(all.cluster.tolerance, cluster.tolerance);
  EXPECT_EQ(all.max_scene_extent, 50.0);
  EXPECT_EQ(all.max_pixel_spacing_factor, 10.0);

  EXPECT_NO_THROW(voxel.validate());
  EXPECT_NO_THROW(plane.validate());
  EXPECT_NO_THROW(above.validate());
  EXPECT_NO_THROW(cluster.validate());
  EXPECT_NO_THROW(all.validate());
}

TEST(SegmentationParams, ValidateNamesFieldAndValue) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  {
    seg::VoxelParams p;
    p.voxel_size = -0.5;
    expectInvalid([&] { p.validate(); }, {"voxel_size", "-0.5"});
    p.voxel_size = nan;
    expectInvalid([&] { p.validate(); }, {"voxel_size", "nan"});
  }
  {
    seg::TablePlaneParams p;
    p.distance_threshold = 0.0;
    expectInvalid([&] { p.validate(); }, {"distance_threshold", "= 0"});
  }
  {
    seg::TablePlaneParams p;
    p.max_iterations = -3;
    expectInvalid([&] { p.validate(); }, {"max_iterations", "-3"});
  }
  {
    seg::TablePlaneParams p;
    p.min_inliers = 2;
    expectInvalid([&] { p.validate(); }, {"min_inliers", "2"});
  }
  {
    seg::TablePlaneParams p;
    p.probability = 1.0;
    expectInvalid([&] { p.validate(); }, {"probability", "1"});
  }
  {
    seg::AboveTableParams p;
    p.max_height = 0.001;
    expectInvalid([&] { p.validate(); }, {"max_height", "0.001", "min_height"});
  }
  {
    seg::AboveTableParams p;
    p.min_height = -std::numeric_limits<double>::infinity();
    expectInvalid([&] { p.validate(); }, {"min_height", "inf"});
  }
  {
    seg::ClusterParams p;
    p.tolerance = -0.02;
    expectInvalid([&] { p.validate(); }, {"tolerance", "-0.02"});
  }
  {
    seg::ClusterParams p;
    p.min_size = 0;
    expectInvalid([&] { p.validate(); }, {"min_size", "0"});
  }
  {
    seg::ClusterParams p;
    p.max_size = 50;
    expectInvalid([&] { p.validate(); }, {"max_size", "50", "min_size = 100"});
  }
  {
    seg::TabletopParams p;
    p.plane.distance_threshold = -1.0;
    expectInvalid([&] { p.validate(); }, {"TabletopParams", "plane.distance_threshold", "-1"});
  }
  {
    seg::TabletopParams p;
    p.cluster.tolerance = 0.0;
    expectInvalid([&] { p.validate(); }, {"cluster.tolerance", "0"});
  }
  {
    seg::TabletopParams p;
    p.max_scene_extent = -1.0;
    expectInvalid([&] { p.validate(); }, {"max_scene_extent", "-1"});
  }
  {
    seg::TabletopParams p;
    p.voxel.voxel_size = -0.01;
    expectInvalid([&] { p.validate(); }, {"voxel.voxel_size", "-0.01"});
  }
}

TEST(SegmentationParams, StagesThrowOnBrokenContracts) {
  SyntheticScene<pcl::PointXYZ> scene;
  scene.addTable();
  seg::TabletopParams bad;
  bad.cluster.min_size = 0;
  expectInvalid([&] { seg::segmentTabletop(scene.cloud, bad); }, {"cluster.min_size"});

  const pcl::Indices out_of_range{0, 1, static_cast<pcl::index_t>(scene.cloud.size())};
  expectInvalid([&] { seg::findTablePlane(scene.cloud, out_of_range, {}); },
                {"findTablePlane", "out of range"});
  expectInvalid([&] { seg::extractClusters(scene.cloud, out_of_range, {}); },
                {"extractClusters", "out of range"});
  expectInvalid([&] { seg::voxelDownsample(scene.cloud, {-1}, {}); }, {"voxelDownsample", "-1"});
  expectInvalid([&] { seg::planeInliers(scene.cloud, {0}, Eigen::Vector4f(0, 1, 0, 0), 0.0); },
                {"distance_threshold"});
}

TEST(SegmentationParams, StatusNames) {
  EXPECT_EQ(seg::toString(TabletopStatus::SceneUnitsSuspect), "SceneUnitsSuspect");
  EXPECT_EQ(seg::toString(TabletopStatus::NoCluster), "NoCluster");
  EXPECT_EQ(seg::toString(seg::TablePlaneStatus::TooFewInliers), "TooFewInliers");
  EXPECT_EQ(seg::toString(seg::AboveTableStatus::DegenerateHull), "DegenerateHull");
  EXPECT_EQ(seg::toString(seg::ClusterMethod::PclOrganized), "PclOrganized");
}

// ---------------------------------------------------------------------------------------------
// Stages on synthetic scenes.

TEST(FiniteIndices, SkipsNaNAndInf) {
  pcl::PointCloud<pcl::PointXYZ> cloud(4, 2);  // organized 4x2
  for (auto& p : cloud)
    p = makePoint<pcl::PointXYZ>(1, 2, 3);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cloud.at(1, 0).z = nan;
  cloud.at(3, 1).x = std::numeric_limits<float>::infinity();
  cloud.is_dense = false;
  EXPECT_EQ(seg::finiteIndices(cloud), (pcl::Indices{0, 2, 3, 4, 5, 6}));
  EXPECT_TRUE(seg::finiteIndices(pcl::PointCloud<pcl::PointXYZ>()).empty());
}

TEST(VoxelDownsample, ReducesAndKeepsFrame) {
  SyntheticScene<pcl::PointXYZ> scene;
  scene.addTable();
  scene.cloud.sensor_origin_ = Eigen::Vector4f(0.1f, 0.2f, 0.3f, 0.0f);
  const pcl::Indices all = seg::finiteIndices(scene.cloud);
  seg::VoxelParams p;
  const auto copy = seg::voxelDownsample(scene.cloud, all, p);
  EXPECT_EQ(copy.size(), scene.cloud.size());  // voxel_size 0: the indexed points
  p.voxel_size = 0.03;  // the table (y = 0.4 +- 1 mm) lies inside one layer of 3 cm voxels
  const auto reduced = seg::voxelDownsample(scene.cloud, all, p);
  // 1 m x 1 m table at 3 cm: 34 x 34 voxels, give or take the boundary columns.
  EXPECT_GE(reduced.size(), 33u * 33u);
  EXPECT_LE(reduced.size(), 35u * 35u);
  EXPECT_EQ(reduced.height, 1u);
  EXPECT_TRUE(reduced.sensor_origin_.isApprox(scene.cloud.sensor_origin_));
}

TEST(VoxelDownsample, TooManyVoxelsGivesTheFiniteIndexedPoints) {
  // A stray point 1e5 m away with 1 cm voxels: 1e21 cells, beyond VoxelGrid's int32 voxel
  // index (PCL would return its whole input, NaN and unindexed points included). Expected: the
  // indexed finite points themselves, every one finite.
  SyntheticScene<pcl::PointXYZ> scene;
  scene.addTable();
  scene.cloud.push_back(makePoint<pcl::PointXYZ>(1e5f, 1e5f, 1e5f));
  scene.cloud.push_back(makePoint<pcl::PointXYZ>(std::numeric_limits<float>::quiet_NaN(), 0, 0));
  scene.cloud.width = static_cast<std::uint32_t>(scene.cloud.size());
  scene.cloud.height = 1;
  pcl::Indices all(scene.cloud.size());
  for (std::size_t i = 0; i < all.size(); ++i)
    all[i] = static_cast<pcl::index_t>(i);
  pcl::Indices some(all.begin() + 10, all.end());  // the first 10 points left out
  seg::VoxelParams p;
  p.voxel_size = 0.01;
  const auto out = seg::voxelDownsample(scene.cloud, some, p);
  EXPECT_EQ(out.size(), some.size() - 1);  // all but the NaN point
  for (const auto& q : out)
    EXPECT_TRUE(pcl::isXYZFinite(q));
  EXPECT_TRUE(out.back().getVector3fMap().isApprox(Eigen::Vector3f::Constant(1e5f)));
}

TEST(TablePlane, FindsSyntheticTableOrientedTowardsSensor) {
  SyntheticScene<pcl::PointXYZ> scene;
  scene.addTable();
  scene.addBox(0.0f, 1.0f, 0.05f, 0.05f, 0.1f);
  const seg::TablePlane plane =
      seg::findTablePlane(scene.cloud, seg::finiteIndices(scene.cloud), {});
  ASSERT_EQ(plane.status, seg::TablePlaneStatus::Found);
  // y = 0.4 seen from the origin: normal (0, -1, 0), d = 0.4 (origin 0.4 m above the table).
  EXPECT_NEAR(plane.coefficients[0], 0.0f, 1e-3f);
  EXPECT_NEAR(plane.coefficients[1], -1.0f, 1e-4f);
  EXPECT_NEAR(plane.coefficients[2], 0.0f, 1e-3f);
  EXPECT_NEAR(plane.coefficients[3], 0.4f, 1e-3f);
  EXPECT_NEAR(plane.coefficients.head<3>().norm(), 1.0f, 1e-6f);
  const std::size_t table_points = scene.cloud.size() - scene.boxes[0].size();
  EXPECT_EQ(plane.inliers.size(), table_points);
  EXPECT_GT(plane.iterations, 0);

  // A sensor below the table flips the normal.
  scene.cloud.sensor_origin_ = Eigen::Vector4f(0.0f, 1.0f, 0.0f, 0.0f);
  const seg::TablePlane below =
      seg::findTablePlane(scene.cloud, seg::finiteIndices(scene.cloud), {});
  ASSERT_TRUE(below.found());
  EXPECT_NEAR(below.coefficients[1], 1.0f, 1e-4f);
  EXPECT_NEAR(below.coefficients[3], -0.4f, 1e-3f);
}

TEST(TablePlane, DataOutcomesAreStatuses) {
  pcl::PointCloud<pcl::PointXYZ> three;
  three.push_back(makePoint<pcl::PointXYZ>(0, 0, 1));
  three.push_back(makePoint<pcl::PointXYZ>(1, 0, 1));
  three.push_back(makePoint<pcl::PointXYZ>(0, 1, 1));
  EXPECT_EQ(seg::findTablePlane(three, {0, 1, 2}, {}).status, seg::TablePlaneStatus::TooFewInliers);
  seg::TablePlaneParams three_ok;
  three_ok.min_inliers = 3;
  const auto found = seg::findTablePlane(three, {0, 1, 2}, three_ok);
  EXPECT_EQ(found.status, seg::TablePlaneStatus::Found);
  EXPECT_NEAR(std::abs(found.coefficients[2]), 1.0f, 1e-6f);
  EXPECT_EQ(seg::findTablePlane(three, {0, 1}, three_ok).status, seg::TablePlaneStatus::NoPlane);
  EXPECT_EQ(seg::findTablePlane(three, {}, three_ok).status, seg::TablePlaneStatus::NoPlane);

  pcl::PointCloud<pcl::PointXYZ> line;  // collinear: no plane, and no PCL error spam
  for (int i = 0; i < 1000; ++i)
    line.push_back(makePoint<pcl::PointXYZ>(0.001f * static_cast<float>(i), 0.0f, 1.0f));
  const auto on_line = seg::findTablePlane(line, seg::finiteIndices(line), {});
  EXPECT_EQ(on_line.status, seg::TablePlaneStatus::NoPlane);
  EXPECT_TRUE(on_line.inliers.empty());

  pcl::PointCloud<pcl::PointXYZ> fog;  // uniform in a 1 m cube: a 2 cm slab holds ~2% = 40
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  for (int i = 0; i < 2000; ++i)
    fog.push_back(makePoint<pcl::PointXYZ>(u(rng), u(rng), 2.0f + u(rng)));
  EXPECT_EQ(seg::findTablePlane(fog, seg::finiteIndices(fog), {}).status,
            seg::TablePlaneStatus::TooFewInliers);
}

TEST(AboveTable, PrismKeepsBoxDropsTableAndOutside) {
  SyntheticScene<pcl::PointXYZ> scene;
  scene.addTable();
  scene.addBox(0.0f, 1.0f, 0.05f, 0.05f, 0.1f);
  const pcl::Indices finite = seg::finiteIndices(scene.cloud);
  // A point floating outside the table's hull, at box height.
  scene.cloud.push_back(makePoint<pcl::PointXYZ>(0.9f, 0.35f, 1.0f));
  scene.cloud.width = static_cast<std::uint32_t>(scene.cloud.size());
  pcl::Indices with_outside = finite;
  with_outside.push_back(static_cast<pcl::index_t>(scene.cloud.size() - 1));

  const auto plane = seg::findTablePlane(scene.cloud, finite, {});
  ASSERT_TRUE(plane.found());
  const auto hull = seg::tableHull(scene.cloud, plane.inliers, plane.coefficients);
  EXPECT_GE(hull.size(), 4u);
  EXPECT_LE(hull.size(), 64u);
  const auto above = seg::aboveTableIndices(scene.cloud, with_outside, plane, {});
  ASSERT_EQ(above.status, seg::AboveTableStatus::Ok);
  EXPECT_EQ(above.hull_size, hull.size());
  EXPECT_EQ(above.indices, scene.boxes[0]);  // the box, not the table, not the outside point

  seg::AboveTableParams low;  // a prism of 5 mm..5 cm keeps only the box's lower rows
  low.min_height = 0.005;
  low.max_height = 0.05;
  const auto lower = seg::aboveTableIndices(scene.cloud, finite, hull, low);
  EXPECT_GT(lower.indices.size(), 0u);
  EXPECT_LT(lower.indices.size(), scene.boxes[0].size() / 2);

  seg::TablePlane none;  // plane not found -> status, no hull
  EXPECT_EQ(seg::aboveTableIndices(scene.cloud, finite, none, {}).status,
            seg::AboveTableStatus::NoPlane);
  EXPECT_EQ(
      seg::aboveTableIndices(scene.cloud, finite, pcl::PointCloud<pcl::PointXYZ>(), {}).status,
      seg::AboveTableStatus::DegenerateHull);
  EXPECT_TRUE(seg::tableHull(scene.cloud, {0, 1}, plane.coefficients).empty());
}

TEST(ExtractClusters, SortedBySizeThenSmallestIndex) {
  std::vector<pcl::PointIndices> clusters(4);
  clusters[0].indices = {9, 3};
  clusters[1].indices = {5, 7, 6};
  clusters[2].indices = {8, 1};
  clusters[3].indices = {0};
  seg::sortClusters(clusters);
  EXPECT_EQ(clusters[0].indices, (pcl::Indices{5, 6, 7}));
  EXPECT_EQ(clusters[1].indices, (pcl::Indices{1, 8}));
  EXPECT_EQ(clusters[2].indices, (pcl::Indices{3, 9}));
  EXPECT_EQ(clusters[3].indices, (pcl::Indices{0}));
}

/** Random blobs (unorganized), so that chains of links decide the components: the grid
 * algorithm must agree with pcl::EuclideanClusterExtraction at several tolerances. */
TEST(ExtractClusters, GridMatchesPclOnRandomBlobs) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<float> centre(-0.5f, 0.5f);
  std::normal_distribution<float> spread(0.0f, 0.03f);
  for (int blob = 0; blob < 25; ++blob) {
    const Eigen::Vector3f c(centre(rng), centre(rng), 1.5f + centre(rng));
    for (int i = 0; i < 400; ++i)
      cloud.push_back(
          makePoint<pcl::PointXYZ>(c.x() + spread(rng), c.y() + spread(rng), c.z() + spread(rng)));
  }
  cloud.width = static_cast<std::uint32_t>(cloud.size());
  cloud.height = 1;
  const pcl::Indices all = seg::finiteIndices(cloud);
  for (const double tolerance : {0.005, 0.01, 0.02, 0.05}) {
    seg::ClusterParams grid;
    grid.tolerance = tolerance;
    grid.min_size = 1;
    seg::ClusterParams reference = grid;
    reference.method = seg::ClusterMethod::PclKdTree;
    const auto a = seg::extractClusters(cloud, all, grid);
    const auto b = seg::extractClusters(cloud, all, reference);
    EXPECT_TRUE(sameClusters(a, b))
        << "tolerance " << tolerance << ": grid " << a.size() << " clusters, PCL " << b.size();
  }
}

/** The whole pipeline on the synthetic scene, for each precompiled point type. */
template <typename PointT>
class SegmentTabletopTyped : public ::testing::Test {};
using PrecompiledTypes = ::testing::Types<pcl::PointXYZ, pcl::PointXYZRGB, pcl::PointXYZRGBA>;
TYPED_TEST_SUITE(SegmentTabletopTyped, PrecompiledTypes, ::testing::internal::DefaultNameGenerator);

TYPED_TEST(SegmentTabletopTyped, TwoBoxesTwoClusters) {
  SyntheticScene<TypeParam> scene;
  scene.addTable();
  scene.addBox(-0.2f, 1.0f, 0.05f, 0.05f, 0.10f);  // smaller
  scene.addBox(0.2f, 1.2f, 0.08f, 0.06f, 0.15f);   // larger
  const auto result = seg::segmentTabletop(scene.cloud);
  ASSERT_EQ(result.status, TabletopStatus::Ok) << result.message;
  EXPECT_TRUE(result.message.empty());
  ASSERT_EQ(result.clusters.size(), 2u);
  EXPECT_EQ(result.clusters[0].indices, scene.boxes[1]);  // largest first
  EXPECT_EQ(result.clusters[1].indices, scene.boxes[0]);
  EXPECT_EQ(result.above_table.size(), scene.boxes[0].size() + scene.boxes[1].size());
  EXPECT_EQ(result.plane.inliers.size(),
            scene.cloud.size() - scene.boxes[0].size() - scene.boxes[1].size());
  EXPECT_EQ(result.finite_points, scene.cloud.size());
  EXPECT_LT(result.plane_search_points, scene.cloud.size());  // voxel grid on by default
  EXPECT_GE(result.timing.total_ms, result.timing.cluster_ms);
}

// ---------------------------------------------------------------------------------------------
// Bad inputs: a clear status, never an exception or a crash.

TEST(SegmentTabletopBadInput, EmptyCloud) {
  const auto r = seg::segmentTabletop(pcl::PointCloud<pcl::PointXYZ>());
  EXPECT_EQ(r.status, TabletopStatus::EmptyCloud);
  EXPECT_FALSE(r.message.empty());
  EXPECT_TRUE(r.clusters.empty());
}

TEST(SegmentTabletopBadInput, AllNaNOrganizedCloud) {
  pcl::PointCloud<pcl::PointXYZRGBA> cloud(640, 480);
  for (auto& p : cloud)
    p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
  cloud.is_dense = false;
  const auto r = seg::segmentTabletop(cloud);
  EXPECT_EQ(r.status, TabletopStatus::NoFinitePoints) << r.message;
  EXPECT_EQ(r.finite_points, 0u);
}

TEST(SegmentTabletopBadInput, ThreePoints) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.push_back(makePoint<pcl::PointXYZ>(0, 0, 1));
  cloud.push_back(makePoint<pcl::PointXYZ>(1, 0, 1));
  cloud.push_back(makePoint<pcl::PointXYZ>(0, 1, 1));
  const auto r = seg::segmentTabletop(cloud);
  EXPECT_EQ(r.status, TabletopStatus::TooFewPoints) << r.message;

  seg::TabletopParams lenient;  // with min_inliers 3 the plane is found; nothing stands on it
  lenient.plane.min_inliers = 3;
  lenient.voxel.voxel_size = 0.0;
  const auto r3 = seg::segmentTabletop(cloud, lenient);
  EXPECT_EQ(r3.status, TabletopStatus::NoCluster) << r3.message;
  EXPECT_EQ(r3.plane.inliers.size(), 3u);
}

TEST(SegmentTabletopBadInput, NoPlane) {
  pcl::PointCloud<pcl::PointXYZ> fog;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  for (int i = 0; i < 5000; ++i)
    fog.push_back(makePoint<pcl::PointXYZ>(u(rng), u(rng), 2.0f + u(rng)));
  seg::TabletopParams p;
  p.voxel.voxel_size = 0.0;
  const auto r = seg::segmentTabletop(fog, p);
  EXPECT_EQ(r.status, TabletopStatus::NoPlane) << r.message;
  EXPECT_NE(r.plane.status, seg::TablePlaneStatus::Found);
  EXPECT_NE(r.message.find("min_inliers"), std::string::npos) << r.message;
}

TEST(SegmentTabletopBadInput, PlaneWithoutObjectsIsNoCluster) {
  SyntheticScene<pcl::PointXYZ> scene;
  scene.addTable();
  const auto r = seg::segmentTabletop(scene.cloud);
  EXPECT_EQ(r.status, TabletopStatus::NoCluster) << r.message;
  EXPECT_TRUE(r.plane.found());
  EXPECT_TRUE(r.clusters.empty());

  scene.addBox(0.0f, 1.0f, 0.01f, 0.01f, 0.02f);  // a 2 cm cube: fewer than min_size points
  const auto small = seg::segmentTabletop(scene.cloud);
  EXPECT_EQ(small.status, TabletopStatus::NoCluster) << small.message;
  EXPECT_FALSE(small.above_table.empty());
}

TEST(SegmentTabletopBadInput, MillimetreSceneIsFlagged) {
  // The synthetic scene in millimetres: 1000 mm wide, far beyond max_scene_extent = 50.
  SyntheticScene<pcl::PointXYZ> scene;
  scene.addTable();
  scene.addBox(0.0f, 1.0f, 0.05f, 0.05f, 0.1f);
  for (auto& p : scene.cloud)
    p.getVector3fMap() *= 1000.0f;
  const auto r = seg::segmentTabletop(scene.cloud);
  EXPECT_EQ(r.status, TabletopStatus::SceneUnitsSuspect) << r.message;
  EXPECT_NE(r.message.find("millimetres"), std::string::npos) << r.message;

  seg::TabletopParams off;  // checks off: runs with metre parameters, finds nothing useful
  off.max_scene_extent = 0.0;
  off.max_pixel_spacing_factor = 0.0;
  EXPECT_NE(seg::segmentTabletop(scene.cloud, off).status, TabletopStatus::Ok);
}

TEST(SegmentTabletopBadInput, SmallMillimetreOrganizedSceneIsFlaggedBySpacing) {
  // 40 x 30 pixels, 1 mm apart (units: mm): extent 50 < max_scene_extent, but neighbouring
  // pixels are 1 unit apart, 50x the 2 cm cluster tolerance read as metres.
  pcl::PointCloud<pcl::PointXYZ> cloud(40, 30);
  for (std::uint32_t r = 0; r < cloud.height; ++r)
    for (std::uint32_t c = 0; c < cloud.width; ++c)
      cloud.at(c, r) = makePoint<pcl::PointXYZ>(static_cast<float>(c), static_cast<float>(r), 0.0f);
  const auto result = seg::segmentTabletop(cloud);
  EXPECT_EQ(result.status, TabletopStatus::SceneUnitsSuspect) << result.message;
  EXPECT_NE(result.message.find("adjacent pixels"), std::string::npos) << result.message;
}

// ---------------------------------------------------------------------------------------------
// Determinism.

TEST(SegmentTabletopDeterminism, SameSeedSameResult) {
  SyntheticScene<pcl::PointXYZRGB> scene(5);
  scene.addTable();
  scene.addBox(-0.2f, 1.0f, 0.05f, 0.05f, 0.10f);
  scene.addBox(0.2f, 1.2f, 0.08f, 0.06f, 0.15f);
  seg::TabletopParams p;
  p.plane.seed = 1234;
  const auto a = seg::segmentTabletop(scene.cloud, p);
  const auto b = seg::segmentTabletop(scene.cloud, p);
  ASSERT_EQ(a.status, TabletopStatus::Ok) << a.message;
  EXPECT_EQ(a.plane.coefficients, b.plane.coefficients);  // bitwise
  EXPECT_EQ(a.plane.inliers, b.plane.inliers);
  EXPECT_EQ(a.plane.iterations, b.plane.iterations);
  EXPECT_EQ(a.above_table, b.above_table);
  EXPECT_TRUE(sameClusters(a.clusters, b.clusters));
}

// ---------------------------------------------------------------------------------------------
// Real scenes.

/** The PCL milk scene (a floor, not a table: the "table" stage finds the floor) against
 * milk.pcd, the carton's reference cut. Points are matched by exact coordinates. */
TEST(SegmentTabletopRealData, MilkCartonMatchesReferenceCut) {
  PCL_ICF_REQUIRE_SHARED(scene_path, "pcl/milk_cartoon_all_small_clorox.pcd");
  PCL_ICF_REQUIRE_SHARED(milk_path, "pcl/milk.pcd");
  const auto scene = loadCloud<pcl::PointXYZRGBA>(scene_path);
  const auto milk = loadCloud<pcl::PointXYZ>(milk_path);
  ASSERT_EQ(scene.size(), 640u * 480u);
  ASSERT_EQ(milk.size(), 13704u);

  const auto result = seg::segmentTabletop(scene);
  ASSERT_EQ(result.status, TabletopStatus::Ok) << result.message;

  std::set<Key> reference;
  for (const auto& p : milk)
    reference.insert(keyOf(p));
  std::size_t best = 0, best_overlap = 0;
  for (std::size_t c = 0; c < result.clusters.size(); ++c) {
    std::size_t overlap = 0;
    for (const pcl::index_t i : result.clusters[c].indices)
      overlap += reference.count(keyOf(scene[i]));
    if (overlap > best_overlap) {
      best_overlap = overlap;
      best = c;
    }
  }
  const std::size_t cluster_size = result.clusters[best].indices.size();
  const std::size_t missing = reference.size() - best_overlap;
  const std::size_t extra = cluster_size - best_overlap;
  std::cout << "[ milk     ] cluster " << best << " of " << result.clusters.size() << ": "
            << cluster_size << " points, reference " << reference.size() << ", missing " << missing
            << ", extra " << extra << ", symmetric difference " << missing + extra << " ("
            << std::fixed << std::setprecision(1) << result.timing.total_ms << " ms)\n";
  RecordProperty("milk_symmetric_difference", std::to_string(missing + extra));
  // Measured: the carton is the largest cluster, 13,717 points: missing 0, extra 13 (11 points
  // 4.0-4.1 mm above the floor, just under the reference's cut, and 2 on the carton's top).
  EXPECT_EQ(best, 0u);
  EXPECT_LE(missing + extra, 25u);

  // The same scene as PointXYZ gives the same segmentation.
  const auto xyz = loadCloud<pcl::PointXYZ>(scene_path);
  const auto result_xyz = seg::segmentTabletop(xyz);
  EXPECT_TRUE(sameClusters(result.clusters, result_xyz.clusters));
}

/** Grid clustering equals pcl::EuclideanClusterExtraction (kd-tree and organized search) on the
 * real points above the milk scene's floor. */
TEST(SegmentTabletopRealData, GridClustersEqualPclOnMilkScene) {
  PCL_ICF_REQUIRE_SHARED(scene_path, "pcl/milk_cartoon_all_small_clorox.pcd");
  const auto scene = loadCloud<pcl::PointXYZ>(scene_path);
  const auto result = seg::segmentTabletop(scene);
  ASSERT_EQ(result.status, TabletopStatus::Ok) << result.message;
  seg::ClusterParams p;
  p.min_size = 1;  // every component, singletons too
  const auto grid = seg::extractClusters(scene, result.above_table, p);
  p.method = seg::ClusterMethod::PclOrganized;
  const auto organized = seg::extractClusters(scene, result.above_table, p);
  p.method = seg::ClusterMethod::PclKdTree;
  const auto kdtree = seg::extractClusters(scene, result.above_table, p);
  EXPECT_GT(grid.size(), 10u);
  EXPECT_TRUE(sameClusters(grid, organized));
  EXPECT_TRUE(sameClusters(grid, kdtree));
}

TEST(SegmentTabletopRealData, MilkSceneInMillimetresIsFlagged) {
  PCL_ICF_REQUIRE_SHARED(scene_path, "pcl/milk_cartoon_all_small_clorox.pcd");
  auto scene = loadCloud<pcl::PointXYZ>(scene_path);
  for (auto& p : scene)
    p.getVector3fMap() *= 1000.0f;  // NaN stays NaN
  const auto r = seg::segmentTabletop(scene);
  EXPECT_EQ(r.status, TabletopStatus::SceneUnitsSuspect) << r.message;
  EXPECT_TRUE(r.clusters.empty());
}

TEST(SegmentTabletopRealData, DeterministicOnMilkScene) {
  PCL_ICF_REQUIRE_SHARED(scene_path, "pcl/milk_cartoon_all_small_clorox.pcd");
  const auto scene = loadCloud<pcl::PointXYZ>(scene_path);
  seg::TabletopParams p;
  p.plane.seed = 42;
  const auto a = seg::segmentTabletop(scene, p);
  const auto b = seg::segmentTabletop(scene, p);
  ASSERT_EQ(a.status, TabletopStatus::Ok) << a.message;
  EXPECT_EQ(a.plane.coefficients, b.plane.coefficients);
  EXPECT_EQ(a.plane.inliers, b.plane.inliers);
  EXPECT_TRUE(sameClusters(a.clusters, b.clusters));
}

// mOSD: per-segment precision and recall of the best-matching cluster.
//
// The unit is the labelled segment (label >= 20; object k = labels 10k..10k+9): mOSD gives the
// disjoint parts of an occluded object different labels precisely so that a model-free method is
// not asked to join them (test55's object 15 is two parts, 150 and 151). Best-matching cluster:
// the one holding most of the segment's points. Precision = overlap / cluster size, recall =
// overlap / segment size.
struct SegmentScore {
  unsigned label = 0;
  std::size_t points = 0;
  std::size_t cluster = 0;
  std::size_t cluster_size = 0;
  double precision = 0.0;
  double recall = 0.0;
};

struct MosdExpectation {
  std::string scene;
  std::size_t segments;
  /** Segments that touch another object: Euclidean clustering cannot separate them (no gap of
   * cluster.tolerance), so their best cluster holds the others too; precision not asserted. */
  std::set<unsigned> touching;
  /** Recall floors below the default, with the reason in the test's comment. */
  std::map<unsigned, double> recall_floor;
};

void PrintTo(const MosdExpectation& e, std::ostream* os) {
  *os << e.scene;
}

std::vector<SegmentScore> scoreSegments(const pcl::PointCloud<pcl::PointXYZL>& labels,
                                        const std::vector<pcl::PointIndices>& clusters) {
  std::map<unsigned, std::size_t> segment_size;
  for (const auto& p : labels)
    if (p.label >= 20)
      ++segment_size[p.label];
  std::vector<std::map<unsigned, std::size_t>> overlap(clusters.size());
  for (std::size_t c = 0; c < clusters.size(); ++c)
    for (const pcl::index_t i : clusters[c].indices)
      ++overlap[c][labels[i].label];
  std::vector<SegmentScore> scores;
  for (const auto& [label, n] : segment_size) {
    SegmentScore s;
    s.label = label;
    s.points = n;
    std::size_t best = 0;
    for (std::size_t c = 0; c < clusters.size(); ++c) {
      const auto it = overlap[c].find(label);
      if (it != overlap[c].end() && it->second > best) {
        best = it->second;
        s.cluster = c;
      }
    }
    if (best > 0) {
      s.cluster_size = clusters[s.cluster].indices.size();
      s.precision = static_cast<double>(best) / static_cast<double>(s.cluster_size);
      s.recall = static_cast<double>(best) / static_cast<double>(n);
    }
    scores.push_back(s);
  }
  return scores;
}

class Mosd : public ::testing::TestWithParam<MosdExpectation> {};

TEST_P(Mosd, PrecisionRecallPerSegment) {
  const MosdExpectation& expect = GetParam();
  PCL_ICF_REQUIRE_SHARED(path, "mosd/" + expect.scene + ".pcd");
  const auto scene = loadCloud<pcl::PointXYZRGBA>(path);
  const auto labels = loadCloud<pcl::PointXYZL>(path);
  ASSERT_EQ(scene.size(), labels.size());

  const auto result = seg::segmentTabletop(scene);
  ASSERT_EQ(result.status, TabletopStatus::Ok) << result.message;
  const auto scores = scoreSegments(labels, result.clusters);
  ASSERT_EQ(scores.size(), expect.segments);

  std::ostringstream table;
  table << "[ mosd     ] " << expect.scene << ": " << result.clusters.size() << " clusters, "
        << std::fixed << std::setprecision(1) << result.timing.total_ms << " ms\n"
        << "    segment  points  cluster  size   precision  recall  note\n";
  for (const auto& s : scores) {
    table << "    " << std::setw(7) << s.label << std::setw(8) << s.points << std::setw(9)
          << s.cluster << std::setw(7) << s.cluster_size << std::setprecision(3) << std::setw(12)
          << s.precision << std::setw(8) << s.recall << "  "
          << (expect.touching.count(s.label) ? "touching (merged)" : "") << "\n";
    RecordProperty(expect.scene + "_" + std::to_string(s.label),
                   "P=" + std::to_string(s.precision) + " R=" + std::to_string(s.recall));
  }
  std::cout << table.str();

  // Floors just under the measured values (see the report table in the test output).
  constexpr double kPrecision = 0.94;  // lowest measured on a separated segment: 0.946
  constexpr double kRecall = 0.97;     // lowest measured, overhangs aside: 0.976
  for (const auto& s : scores) {
    if (s.points < 500)
      continue;
    const auto floor = expect.recall_floor.find(s.label);
    EXPECT_GE(s.recall, floor == expect.recall_floor.end() ? kRecall : floor->second)
        << expect.scene << " segment " << s.label;
    if (!expect.touching.count(s.label)) {
      EXPECT_GE(s.precision, kPrecision) << expect.scene << " segment " << s.label;
    }
  }
}

// The same scoring after the localizer's second step: every Euclidean cluster split where its
// surface turns concave (splitByConvexity, LCCP over supervoxels), model-free, as the localizer
// does to a cluster too big for its model. Printed as a report
// (doc/experiments/2026-11-28-convexity-split-mosd.md, "mOSD"). Asserted, on every segment of at
// least 500 points: its best convexity segment is one object (precision >= 0.95: at most 5% of it
// another object's points; Euclidean clustering gives 0.07-0.54 on the touching and stacked ones);
// and over a scene at least half the objects keep 90% of their points in one segment (the split may
// cut an object, not most of them: the localizer still searches the whole cluster when no segment
// is accepted).
TEST_P(Mosd, ConvexitySplitPerSegment) {
  const MosdExpectation& expect = GetParam();
  PCL_ICF_REQUIRE_SHARED(path, "mosd/" + expect.scene + ".pcd");
  const auto scene = loadCloud<pcl::PointXYZRGBA>(path);
  const auto labels = loadCloud<pcl::PointXYZL>(path);
  const auto result = seg::segmentTabletop(scene);
  ASSERT_EQ(result.status, TabletopStatus::Ok) << result.message;
  std::vector<pcl::PointIndices> segments;
  for (const auto& cluster : result.clusters)
    for (auto& segment : seg::splitByConvexity(scene, cluster))
      segments.push_back(std::move(segment));
  const auto before = scoreSegments(labels, result.clusters);
  const auto after = scoreSegments(labels, segments);
  ASSERT_EQ(after.size(), expect.segments);

  std::ostringstream table;
  table << "[ mosd lccp] " << expect.scene << ": " << result.clusters.size() << " clusters -> "
        << segments.size() << " convexity segments\n"
        << "    segment  points  precision  recall (clusters: precision  recall)\n";
  for (std::size_t k = 0; k < after.size(); ++k)
    table << "    " << std::setw(7) << after[k].label << std::setw(8) << after[k].points
          << std::fixed << std::setprecision(3) << std::setw(11) << after[k].precision
          << std::setw(8) << after[k].recall << "  " << std::setw(18) << before[k].precision
          << std::setw(8) << before[k].recall << "\n";
  std::cout << table.str();

  std::size_t judged = 0, whole = 0;
  for (const auto& segment : after) {
    if (segment.points < 500)
      continue;
    ++judged;
    whole += segment.recall >= 0.9 ? 1 : 0;
    EXPECT_GE(segment.precision, 0.95) << expect.scene << " segment " << segment.label;
  }
  EXPECT_GE(2 * whole, judged) << expect.scene;
}

// test0: two separate boxes. test16: stacked boxes, one touching pile. test31: cylinders 20 and
// 40 stand in contact. test55 (complex): eight objects form one touching group and 40/50 another;
// 40, 50 and 80 stand at the edge of the visible table, part of them beyond the convex hull of
// its points, where the prism does not reach (40: 3,535 of its 7,025 points, 50: 1,253 of
// 12,475, 80: 755 of 3,675).
INSTANTIATE_TEST_SUITE_P(
    RealScenes, Mosd,
    ::testing::Values(MosdExpectation{"test0", 2, {}, {}},
                      MosdExpectation{"test16", 3, {20, 30, 40}, {}},
                      MosdExpectation{"test31", 3, {20, 40}, {}},
                      MosdExpectation{"test55",
                                      15,
                                      {20, 30, 40, 50, 60, 70, 90, 100, 110, 120},
                                      {{40, 0.48}, {50, 0.89}, {80, 0.78}}}),
    [](const ::testing::TestParamInfo<MosdExpectation>& info) { return info.param.scene; });

}  // namespace
