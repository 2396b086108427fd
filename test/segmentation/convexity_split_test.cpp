// The convexity split (convexity_split.h: PCL's supervoxels + LCCP, Stein et al. CVPR 2014) on
// its own. Oracle: the depth-camera simulator labels every pixel with the object it saw, so
// each segment's points can be checked against the box they came from. Two boxes that touch
// (a small one standing against the front of a tall one) meet in a concave crease and must
// come out as two segments, one per box (and at most a few small fragments of the crease
// itself); a box alone has only convex edges and stays whole.
#include "synthetic/depth_camera.h"
#include "synthetic/synthetic_models.h"

#include <pcl/common/io.h>
#include <pcl/icf/segmentation/convexity_split.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace seg = pcl::icf::segmentation;
using pcl::icf::synthetic::SyntheticModel;

/** A rendered table top, its objects' points as one cluster (what Euclidean clustering gives
 * for objects that touch), and for every point of the cluster the label of its object. */
struct TouchingBoxes {
  pcl::PointCloud<pcl::PointXYZRGBA> cloud;
  pcl::PointIndices cluster;
  std::map<int, int> object_of;          ///< cloud index -> object label (1, 2, ...)
  std::map<int, std::size_t> points_of;  ///< object label -> its points in the cluster
};

SyntheticModel box(const char* name, double sx, double sy, double sz) {
  return SyntheticModel{name, pcl::icf::synthetic::makeBox(sx, sy, sz),
                        pcl::icf::synthetic::Symmetry::box(sx, sy, sz),
                        Eigen::Vector3f(0.8f, 0.3f, 0.2f)};
}

/** A tall box (10 x 10 x 20 cm) in the table's middle and, when \a with_small, a small box
 * (10 x 8 x 6 cm) standing against its front face, the side the camera looks from (the
 * table-top camera: 60 cm above the table, tilted 45 degrees; makeTabletopScene). Depth noise
 * of a Kinect at this range (1.5 mm at 1 m, seeded), without outliers: the split is given a
 * cluster after segmentation, which has dropped the far strays. */
TouchingBoxes render(bool with_small) {
  std::vector<SyntheticModel> models = {box("tall", 0.10, 0.10, 0.20)};
  std::vector<Eigen::Vector3d> placements = {Eigen::Vector3d(0.0, 0.0, 0.0)};
  if (with_small) {
    models.push_back(box("small", 0.10, 0.08, 0.06));
    // Centre 5 + 4 cm in front of the tall box's centre: the two faces touch.
    placements.push_back(Eigen::Vector3d(0.0, -0.09, 0.0));
  }
  pcl::icf::synthetic::ScanNoise noise;
  noise.outlier_ratio = 0.0;
  noise.seed = 17;
  const auto scene = pcl::icf::synthetic::makeTabletopScene(
      models, placements, pcl::icf::synthetic::CameraIntrinsics(), noise);
  TouchingBoxes out;
  pcl::copyPointCloud(*scene.scan.cloud, out.cloud);
  for (std::size_t i = 0; i < scene.scan.labels.size(); ++i) {
    const int label = scene.scan.labels[i];
    if (label >= 1 && std::isfinite(out.cloud[i].z)) {
      out.cluster.indices.push_back(static_cast<int>(i));
      out.object_of[static_cast<int>(i)] = label;
      ++out.points_of[label];
    }
  }
  return out;
}

/** How many of \a segment's points came from each object. */
std::map<int, std::size_t> objectsIn(const pcl::PointIndices& segment, const TouchingBoxes& s) {
  std::map<int, std::size_t> count;
  for (const int i : segment.indices)
    ++count[s.object_of.at(i)];
  return count;
}

TEST(ConvexitySplit, TwoTouchingBoxesGiveOneSegmentEach) {
  const TouchingBoxes s = render(true);
  ASSERT_EQ(s.points_of.size(), 2u);
  ASSERT_GT(s.points_of.at(2), 1000u) << "the small box must be well in view";
  const auto segments = seg::splitByConvexity(s.cloud, s.cluster);
  std::ostringstream composition;
  for (const auto& segment : segments) {
    composition << "[";
    for (const auto& kv : objectsIn(segment, s))
      composition << " box " << kv.first << ": " << kv.second;
    composition << " ]";
  }
  SCOPED_TRACE("segments " + composition.str() + ", box 1: " + std::to_string(s.points_of.at(1)) +
               ", box 2: " + std::to_string(s.points_of.at(2)));
  // The two largest segments are the boxes. LCCP also leaves the supervoxels along the crease
  // (3 cm seeds straddling it, their normals half of one box and half of the other) as small
  // segments of their own, above min_segment_points: the localizer tries them too, and the
  // verification drops them. They may hold at most 10% of the cluster (a seed-wide strip along
  // the 10 cm crease is about 5% of the two boxes' visible surface).
  ASSERT_GE(segments.size(), 2u);
  std::map<int, int> segment_of_object;
  for (std::size_t k = 0; k < 2; ++k) {
    const auto count = objectsIn(segments[k], s);
    const auto major =
        std::max_element(count.begin(), count.end(),
                         [](const auto& a, const auto& b) { return a.second < b.second; });
    segment_of_object[major->first] = static_cast<int>(k);
    const double purity =
        static_cast<double>(major->second) / static_cast<double>(segments[k].indices.size());
    const double recall =
        static_cast<double>(major->second) / static_cast<double>(s.points_of.at(major->first));
    // A box's segment holds its points only (a supervoxel goes whole to one side, and the
    // crease's mixed ones went to the small segments: 3% of leeway for one of them), and all
    // of its points but the crease strip (up to 10% of them).
    EXPECT_GE(purity, 0.97) << "segment " << k << " (box " << major->first << ")";
    EXPECT_GE(recall, 0.90) << "segment " << k << " (box " << major->first << ")";
  }
  EXPECT_EQ(segment_of_object.size(), 2u) << "each box must have its own segment";
  std::size_t rest = 0;
  for (std::size_t k = 2; k < segments.size(); ++k)
    rest += segments[k].indices.size();
  EXPECT_LE(static_cast<double>(rest), 0.1 * static_cast<double>(s.cluster.indices.size()));
  // Largest first (the header's promise).
  for (std::size_t k = 1; k < segments.size(); ++k)
    EXPECT_GE(segments[k - 1].indices.size(), segments[k].indices.size());
}

TEST(ConvexitySplit, ABoxAloneStaysWhole) {
  const TouchingBoxes s = render(false);
  const auto segments = seg::splitByConvexity(s.cloud, s.cluster);
  ASSERT_EQ(segments.size(), 1u);
  // Its own edges are convex: the one segment holds the box, at most the odd supervoxel on a
  // grazing face (fewer than min_segment_points, dropped) left out.
  EXPECT_GE(static_cast<double>(segments[0].indices.size()),
            0.97 * static_cast<double>(s.cluster.indices.size()));
}

TEST(ConvexitySplit, TooSmallAClusterIsReturnedAsItIs) {
  // Fewer than 2 x min_segment_points points cannot make two segments: the cluster comes back
  // unchanged, whatever its shape (here the touching boxes' first 299 points).
  const TouchingBoxes s = render(true);
  pcl::PointIndices small;
  small.indices.assign(s.cluster.indices.begin(), s.cluster.indices.begin() + 299);
  const auto segments = seg::splitByConvexity(s.cloud, small);
  ASSERT_EQ(segments.size(), 1u);
  EXPECT_EQ(segments[0].indices, small.indices);
}

TEST(ConvexitySplit, SameCloudSameSegments) {
  const TouchingBoxes s = render(true);
  const auto a = seg::splitByConvexity(s.cloud, s.cluster);
  const auto b = seg::splitByConvexity(s.cloud, s.cluster);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k)
    EXPECT_EQ(a[k].indices, b[k].indices) << "segment " << k;
}

}  // namespace
