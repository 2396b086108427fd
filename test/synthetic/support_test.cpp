/**
 * \file support_test.cpp
 * \brief Tests of the synthetic-scene library (synthetic/) itself: synthetic models, depth camera,
 * pose errors.
 */
#include "synthetic/depth_camera.h"
#include "synthetic/mesh_geometry.h"
#include "synthetic/pose_error.h"
#include "synthetic/synthetic_clutter.h"
#include "synthetic/synthetic_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <map>
#include <random>
#include <stdexcept>

namespace {

using namespace pcl::icf::synthetic;

constexpr double kPi = 3.14159265358979323846;

double degToRad(double deg) {
  return deg * kPi / 180.0;
}

Eigen::Matrix3d rotX(double deg) {
  return Eigen::AngleAxisd(degToRad(deg), Eigen::Vector3d::UnitX()).toRotationMatrix();
}

Eigen::Matrix3d rotZ(double deg) {
  return Eigen::AngleAxisd(degToRad(deg), Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

Eigen::Isometry3d makePose(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  pose.translation() = translation;
  return pose;
}

Eigen::Isometry3d rotationOnly(const Eigen::Matrix3d& rotation) {
  return makePose(rotation, Eigen::Vector3d::Zero());
}

/** A fixed, generic box pose in front of the camera. */
Eigen::Isometry3d knownBoxPose() {
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(degToRad(30.0), Eigen::Vector3d::UnitX()) *
                                    Eigen::AngleAxisd(degToRad(40.0), Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(degToRad(20.0), Eigen::Vector3d::UnitZ()))
                                       .toRotationMatrix();
  return makePose(rotation, Eigen::Vector3d(0.03, -0.02, 0.8));
}

/** Unsigned distance (metres) of p (box frame) to the surface of a centred box with half sizes. */
double distanceToBoxSurface(const Eigen::Vector3d& p, const Eigen::Vector3d& half) {
  const Eigen::Vector3d q = p.cwiseAbs() - half;
  if ((q.array() > 0.0).any()) {
    return q.cwiseMax(0.0).norm();  // outside
  }
  return -q.maxCoeff();  // inside: distance to the nearest face
}

/** Counts vertices and faces by number of corners. */
struct MeshCounts {
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::size_t quads = 0;
  std::size_t other = 0;
};

MeshCounts countMesh(const pcl::PolygonMesh& mesh) {
  MeshCounts counts;
  counts.vertices = static_cast<std::size_t>(mesh.cloud.width) * mesh.cloud.height;
  for (const auto& polygon : mesh.polygons) {
    if (polygon.vertices.size() == 3) {
      ++counts.triangles;
    } else if (polygon.vertices.size() == 4) {
      ++counts.quads;
    } else {
      ++counts.other;
    }
  }
  return counts;
}

/** Analytic volume (m^3) of each named model, from the documented dimensions. */
double analyticVolume(const std::string& name) {
  const auto hex_area = [](double r) { return 1.5 * std::sqrt(3.0) * r * r; };
  if (name == "Box5") {
    return 0.14 * 0.09 * 0.05;
  }
  if (name == "EisKaffe") {
    return kPi * 0.05 * 0.05 * 0.15;
  }
  if (name == "YellowRoundSalt") {
    return kPi * 0.045 * 0.045 * 0.13;
  }
  if (name == "Amicelly") {
    return hex_area(0.04) * 0.12;
  }
  if (name == "Cup") {
    const double r0 = 0.035;
    const double r1 = 0.045;
    return kPi * 0.10 / 3.0 * (r0 * r0 + r0 * r1 + r1 * r1);
  }
  if (name == "Statue") {
    return 0.10 * 0.07 * 0.03 + 0.04 * 0.05 * 0.09 + hex_area(0.02) * 0.05;
  }
  throw std::invalid_argument(name);
}

using QuantizedPoint = std::array<std::int64_t, 3>;

QuantizedPoint quantize(const Eigen::Vector3d& p) {
  return {std::llround(p.x() * 1e6), std::llround(p.y() * 1e6), std::llround(p.z() * 1e6)};
}

// --- synthetic models --------------------------------------------------------------------------

TEST(SyntheticModels, ThesisModelCounts) {
  // The vertex and face counts of each hand-built mesh; the Cup and the Statue mix quads and
  // triangles, so only their sum is fixed (kNone: that count is not checked on its own).
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  struct Expected {
    const char* name;
    pcl::PolygonMesh (*make)();
    std::size_t vertices, quads, triangles, faces;
  };
  const Expected expected[] = {
      {"Box5", makeBox5, 24, 6, 0, 6},
      {"YellowRoundSalt", makeYellowRoundSalt, 130, 32, 64, 96},
      {"EisKaffe", makeEisKaffe, 102, 25, 50, 75},
      {"Amicelly", makeAmicelly, 38, 0, 24, 24},
      {"Cup", [] { return makeCup(); }, 98, kNone, kNone, 72},
      {"Statue", makeStatue, 86, kNone, kNone, 36},
  };
  for (const Expected& e : expected) {
    SCOPED_TRACE(e.name);
    const MeshCounts counts = countMesh(e.make());
    EXPECT_EQ(counts.vertices, e.vertices);
    if (e.quads != kNone) {
      EXPECT_EQ(counts.quads, e.quads);
    }
    if (e.triangles != kNone) {
      EXPECT_EQ(counts.triangles, e.triangles);
    }
    EXPECT_EQ(counts.quads + counts.triangles, e.faces);
    EXPECT_EQ(counts.other, 0u);
  }
}

TEST(SyntheticModels, NamesAndErrors) {
  EXPECT_EQ(thesisModelNames(),
            (std::vector<std::string>{"Box5", "EisKaffe", "YellowRoundSalt", "Amicelly"}));
  for (const auto& name : allModelNames()) {
    EXPECT_EQ(thesisModel(name).name, name);
  }
  EXPECT_THROW(thesisModel("Teapot"), std::invalid_argument);
  EXPECT_THROW(makeBox(0.1, 0.0, 0.1), std::invalid_argument);
  EXPECT_THROW(makeCylinder(0.1, 0.1, 2), std::invalid_argument);
}

TEST(SyntheticModels, ClosedWithOutwardNormalsAndCorrectVolume) {
  for (const auto& name : allModelNames()) {
    SCOPED_TRACE(name);
    const pcl::PolygonMesh mesh = thesisModel(name).mesh;
    const double area = surfaceArea(mesh);
    EXPECT_GT(area, 0.0);
    EXPECT_LT(vectorArea(mesh).norm(), 1e-6 * area);
    const double volume = signedVolume(mesh);
    EXPECT_GT(volume, 0.0);
    EXPECT_NEAR(volume / analyticVolume(name), 1.0, 0.03);
  }
}

TEST(SyntheticModels, EveryEdgeHasAnOppositeEdge) {
  for (const auto& name : allModelNames()) {
    SCOPED_TRACE(name);
    const pcl::PolygonMesh mesh = thesisModel(name).mesh;
    const auto vertices = meshVertices(mesh);
    std::map<std::pair<QuantizedPoint, QuantizedPoint>, int> directed_edges;
    for (const auto& polygon : mesh.polygons) {
      const auto& idx = polygon.vertices;
      for (std::size_t k = 0; k < idx.size(); ++k) {
        const auto a = quantize(vertices[idx[k]]);
        const auto b = quantize(vertices[idx[(k + 1) % idx.size()]]);
        ++directed_edges[{a, b}];
      }
    }
    for (const auto& [edge, count] : directed_edges) {
      const auto reverse = directed_edges.find({edge.second, edge.first});
      ASSERT_NE(reverse, directed_edges.end());
      EXPECT_EQ(reverse->second, count);
    }
  }
}

TEST(SyntheticModels, ConvexModelsHaveOutwardFaces) {
  for (const auto& name : {"Box5", "EisKaffe", "YellowRoundSalt", "Amicelly", "Cup"}) {
    SCOPED_TRACE(name);
    const pcl::PolygonMesh mesh = thesisModel(name).mesh;
    const auto vertices = meshVertices(mesh);
    for (const auto& polygon : mesh.polygons) {
      const auto& idx = polygon.vertices;
      const Eigen::Vector3d normal =
          (vertices[idx[1]] - vertices[idx[0]]).cross(vertices[idx[2]] - vertices[idx[0]]);
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (const auto index : idx) {
        centroid += vertices[index];
      }
      centroid /= static_cast<double>(idx.size());
      EXPECT_GT(normal.dot(centroid), 0.0);
    }
  }
}

TEST(SyntheticModels, CentredWithSymmetryAxisAlongZ) {
  for (const auto& name : allModelNames()) {
    SCOPED_TRACE(name);
    const Eigen::AlignedBox3d box = boundingBox(thesisModel(name).mesh);
    EXPECT_LT(box.center().norm(), 3e-4);  // odd-segment cylinders: the axis is at the origin
  }
  const Eigen::AlignedBox3d box5 = boundingBox(makeBox5());
  EXPECT_TRUE(box5.sizes().isApprox(Eigen::Vector3d(0.14, 0.09, 0.05), 1e-6));
  const Eigen::AlignedBox3d salt = boundingBox(makeYellowRoundSalt());
  EXPECT_NEAR(salt.sizes().z(), 0.13, 1e-6);
  EXPECT_NEAR(salt.max().x(), 0.045, 1e-6);
}

TEST(SyntheticModels, DiscreteSymmetryGroupsMapTheMeshOntoItself) {
  for (const auto& name : allModelNames()) {
    const SyntheticModel model = thesisModel(name);
    if (model.symmetry.kind != Symmetry::Kind::Discrete) {
      continue;
    }
    SCOPED_TRACE(name);
    const auto vertices = meshVertices(model.mesh);
    for (const auto& s : model.symmetry.group) {
      for (const auto& v : vertices) {
        double best = 1e9;
        for (const auto& w : vertices) {
          best = std::min(best, (s * v - w).norm());
        }
        EXPECT_LT(best, 1e-6);
      }
    }
  }
}

// --- symmetry groups ---------------------------------------------------------------------------

void expectValidGroup(const Symmetry& symmetry) {
  ASSERT_EQ(symmetry.kind, Symmetry::Kind::Discrete);
  const auto& group = symmetry.group;
  const auto contains = [&group](const Eigen::Matrix3d& m) {
    return std::any_of(group.begin(), group.end(),
                       [&m](const Eigen::Matrix3d& g) { return (g - m).norm() < 1e-9; });
  };
  EXPECT_TRUE(contains(Eigen::Matrix3d::Identity()));
  for (std::size_t i = 0; i < group.size(); ++i) {
    EXPECT_TRUE((group[i] * group[i].transpose()).isIdentity(1e-9));
    EXPECT_NEAR(group[i].determinant(), 1.0, 1e-9);
    for (std::size_t j = 0; j < group.size(); ++j) {
      EXPECT_TRUE(contains(group[i] * group[j]));  // closed under composition
      if (i != j) {
        EXPECT_GT((group[i] - group[j]).norm(), 1e-6);  // no duplicates
      }
    }
  }
}

TEST(Symmetry, BoxGroupSizes) {
  EXPECT_EQ(Symmetry::box(0.14, 0.09, 0.05).group.size(), 4u);
  EXPECT_EQ(Symmetry::box(0.1, 0.1, 0.05).group.size(), 8u);
  EXPECT_EQ(Symmetry::box(0.1, 0.05, 0.1).group.size(), 8u);
  EXPECT_EQ(Symmetry::box(0.1, 0.1, 0.1).group.size(), 24u);
  expectValidGroup(Symmetry::box(0.14, 0.09, 0.05));
  expectValidGroup(Symmetry::box(0.1, 0.1, 0.05));
  expectValidGroup(Symmetry::box(0.1, 0.1, 0.1));
}

TEST(Symmetry, PrismAndCylinder) {
  EXPECT_EQ(Symmetry::prism(6).group.size(), 12u);
  expectValidGroup(Symmetry::prism(6));
  expectValidGroup(Symmetry::prism(5));
  EXPECT_THROW(Symmetry::prism(0), std::invalid_argument);
  EXPECT_EQ(Symmetry::cylinder().kind, Symmetry::Kind::Axial);
  EXPECT_TRUE(Symmetry::cylinder().axial_flip);
  EXPECT_FALSE(Symmetry::cylinder(false).axial_flip);
  EXPECT_EQ(Symmetry::none().kind, Symmetry::Kind::None);
}

// --- pose error ----------------------------------------------------------------------------------

TEST(PoseError, RotationAngleIsStableNearZeroAnd180) {
  EXPECT_NEAR(rotationAngleDeg(Eigen::Matrix3d::Identity()), 0.0, 1e-12);
  EXPECT_NEAR(rotationAngleDeg(rotX(1e-4)), 1e-4, 1e-9);
  EXPECT_NEAR(rotationAngleDeg(rotX(179.999)), 179.999, 1e-6);
  EXPECT_NEAR(rotationAngleDeg(rotX(180.0)), 180.0, 1e-9);
  EXPECT_NEAR(rotationAngleDeg(rotZ(-30.0)), 30.0, 1e-9);
  EXPECT_NEAR(angleBetweenDeg(Eigen::Vector3d::UnitX(), Eigen::Vector3d(1.0, 1e-7, 0.0)),
              1e-7 * 180.0 / kPi, 1e-12);
}

TEST(PoseError, ZeroForEveryGroupElement) {
  std::mt19937_64 rng(7);
  for (const auto& name : allModelNames()) {
    const SyntheticModel model = thesisModel(name);
    SCOPED_TRACE(name);
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::Isometry3d truth = randomTabletopPose(rng);
      const PoseError same = poseError(truth, truth, model.symmetry);
      EXPECT_NEAR(same.translation, 0.0, 1e-12);
      EXPECT_NEAR(same.rotation_deg, 0.0, 1e-6);
      EXPECT_NEAR(addS(model.mesh, truth, truth), 0.0, 1e-12);
      for (const auto& s : model.symmetry.group) {
        const Eigen::Isometry3d est = truth * rotationOnly(s);
        const PoseError error = poseError(est, truth, model.symmetry);
        EXPECT_NEAR(error.translation, 0.0, 1e-12);
        EXPECT_NEAR(error.rotation_deg, 0.0, 1e-6);
        EXPECT_NEAR(addS(model.mesh, est, truth), 0.0, 1e-6);
      }
    }
  }
}

TEST(PoseError, KnownPerturbations) {
  const Eigen::Isometry3d truth = knownBoxPose();
  const Eigen::Isometry3d tilted = truth * rotationOnly(rotX(10.0));
  EXPECT_NEAR(poseError(tilted, truth, Symmetry::none()).rotation_deg, 10.0, 1e-9);
  EXPECT_NEAR(poseError(tilted, truth, Symmetry::box(0.14, 0.09, 0.05)).rotation_deg, 10.0, 1e-9);
  EXPECT_NEAR(poseError(tilted, truth, Symmetry::prism(6)).rotation_deg, 10.0, 1e-9);
  EXPECT_NEAR(poseError(tilted, truth, Symmetry::cylinder()).rotation_deg, 10.0, 1e-9);
  // A perturbation in the scene frame has the same angle.
  const Eigen::Isometry3d scene_tilted = rotationOnly(rotX(10.0)) * truth;
  EXPECT_NEAR(poseError(scene_tilted, truth, Symmetry::none()).rotation_deg, 10.0, 1e-9);
  // Box5: Rz(180) is a symmetry, Rz(180 + 10) is 10 degrees off, Rz(90) is 90 off.
  const Symmetry box = Symmetry::box(0.14, 0.09, 0.05);
  EXPECT_NEAR(poseError(truth * rotationOnly(rotZ(190.0)), truth, box).rotation_deg, 10.0, 1e-9);
  EXPECT_NEAR(poseError(truth * rotationOnly(rotZ(90.0)), truth, box).rotation_deg, 90.0, 1e-9);
  // Hexagonal prism: 60 degrees about z is a symmetry, 65 is 5 off.
  EXPECT_NEAR(poseError(truth * rotationOnly(rotZ(65.0)), truth, Symmetry::prism(6)).rotation_deg,
              5.0, 1e-9);

  Eigen::Isometry3d shifted = truth;
  shifted.translation() += Eigen::Vector3d(0.03, 0.04, 0.0);
  const PoseError shift_error = poseError(shifted, truth, Symmetry::none());
  EXPECT_NEAR(shift_error.translation, 0.05, 1e-12);
  EXPECT_NEAR(shift_error.rotation_deg, 0.0, 1e-9);
}

TEST(PoseError, AxialIgnoresRotationAboutTheAxis) {
  const Eigen::Isometry3d truth = knownBoxPose();
  const Symmetry cylinder = Symmetry::cylinder(true);
  const Symmetry cup = Symmetry::cylinder(false);
  for (const double angle : {13.0, 90.0, 180.0, 271.0}) {
    const Eigen::Isometry3d est = truth * rotationOnly(rotZ(angle));
    EXPECT_NEAR(poseError(est, truth, cylinder).rotation_deg, 0.0, 1e-6);
    EXPECT_NEAR(poseError(est, truth, cup).rotation_deg, 0.0, 1e-6);
  }
  const Eigen::Isometry3d upside_down = truth * rotationOnly(rotX(180.0));
  EXPECT_NEAR(poseError(upside_down, truth, cylinder).rotation_deg, 0.0, 1e-6);
  EXPECT_NEAR(poseError(upside_down, truth, cup).rotation_deg, 180.0, 1e-6);
  const Eigen::Isometry3d tilted = truth * rotationOnly(rotX(170.0) * rotZ(33.0));
  EXPECT_NEAR(poseError(tilted, truth, cylinder).rotation_deg, 10.0, 1e-6);
  EXPECT_NEAR(poseError(tilted, truth, cup).rotation_deg, 170.0, 1e-6);
}

TEST(PoseError, AddSAndDiameter) {
  const pcl::PolygonMesh box = makeBox5();
  EXPECT_NEAR(modelDiameter(box), std::sqrt(0.14 * 0.14 + 0.09 * 0.09 + 0.05 * 0.05), 1e-6);
  const Eigen::Isometry3d truth = knownBoxPose();
  EXPECT_NEAR(addS(box, truth, truth), 0.0, 1e-12);
  Eigen::Isometry3d shifted = truth;
  shifted.translation() += Eigen::Vector3d(0.0, 0.0, 0.01);
  const double shifted_error = addS(box, shifted, truth);
  EXPECT_GT(shifted_error, 0.0);
  EXPECT_LE(shifted_error, 0.01 + 1e-9);
}

// --- depth camera --------------------------------------------------------------------------------

TEST(DepthCamera, RandomRotationIsUniformAndProper) {
  std::mt19937_64 rng(3);
  Eigen::Matrix3d mean = Eigen::Matrix3d::Zero();
  constexpr int kSamples = 20000;
  for (int i = 0; i < kSamples; ++i) {
    const Eigen::Matrix3d r = randomRotation(rng);
    ASSERT_TRUE((r * r.transpose()).isIdentity(1e-9));
    ASSERT_NEAR(r.determinant(), 1.0, 1e-9);
    mean += r;
  }
  mean /= kSamples;
  EXPECT_LT(mean.cwiseAbs().maxCoeff(), 0.03);  // E[R] = 0 for the uniform (Haar) distribution

  for (int i = 0; i < 100; ++i) {
    const Eigen::Isometry3d pose = randomTabletopPose(rng, 0.7, 1.1);
    EXPECT_GE(pose.translation().z(), 0.7);
    EXPECT_LE(pose.translation().z(), 1.1);
    EXPECT_LE(pose.translation().head<2>().cwiseAbs().maxCoeff(), 0.15);
  }
}

TEST(DepthCamera, BoxClusterLiesOnTheBoxSurface) {
  const pcl::PolygonMesh box = makeBox5();
  const Eigen::Vector3d half(0.07, 0.045, 0.025);
  const Eigen::Isometry3d pose = knownBoxPose();
  const Eigen::Isometry3d camera_to_box = pose.inverse();
  const ScanNoise noise;  // defaults: 1.5 mm at 1 m, 5 % outliers of +-5 cm
  const auto cluster = renderCluster(box, pose, CameraIntrinsics(), noise);
  ASSERT_GT(cluster->size(), 1000u);
  EXPECT_EQ(cluster->width, cluster->size());
  EXPECT_EQ(cluster->height, 1u);

  const double max_depth = pose.translation().z() + half.norm();
  const double bound = 4.0 * noise.sigma_at_1m * max_depth * max_depth + noise.outlier_range;
  std::size_t within_5mm = 0;
  for (const auto& p : *cluster) {
    const double distance =
        distanceToBoxSurface(camera_to_box * p.getVector3fMap().cast<double>(), half);
    EXPECT_LE(distance, bound + 1e-5);
    if (distance <= 0.005) {
      ++within_5mm;
    }
  }
  EXPECT_GT(static_cast<double>(within_5mm), 0.9 * static_cast<double>(cluster->size()));

  // Without noise every point is on the surface up to float precision.
  const auto exact = renderCluster(box, pose, CameraIntrinsics(), ScanNoise::none());
  EXPECT_EQ(exact->size(), cluster->size());
  for (const auto& p : *exact) {
    EXPECT_LT(distanceToBoxSurface(camera_to_box * p.getVector3fMap().cast<double>(), half), 1e-5);
  }
}

TEST(DepthCamera, ClusterOnlyShowsFacesTowardsTheCamera) {
  // Box5 seen frontally along its z axis: only the -z face, the one nearest to the camera, is
  // visible.
  const pcl::PolygonMesh box = makeBox5();
  const Eigen::Isometry3d pose = makePose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 1.0));
  const auto cluster = renderCluster(box, pose, CameraIntrinsics(), ScanNoise::none());
  ASSERT_FALSE(cluster->empty());
  for (const auto& p : *cluster) {
    EXPECT_NEAR(p.z, 1.0 - 0.025, 1e-5);
  }
  // The face covers about (0.14 * 525 / 0.975) x (0.09 * 525 / 0.975) pixels.
  const double expected = (0.14 * 525.0 / 0.975) * (0.09 * 525.0 / 0.975);
  EXPECT_NEAR(static_cast<double>(cluster->size()) / expected, 1.0, 0.03);
}

TEST(DepthCamera, SameSeedSameCloudDifferentSeedDifferentCloud) {
  const pcl::PolygonMesh mesh = makeEisKaffe();
  const Eigen::Isometry3d pose = knownBoxPose();
  ScanNoise noise;
  noise.seed = 42;
  const auto a = renderCluster(mesh, pose, CameraIntrinsics(), noise);
  const auto b = renderCluster(mesh, pose, CameraIntrinsics(), noise);
  noise.seed = 43;
  const auto c = renderCluster(mesh, pose, CameraIntrinsics(), noise);
  ASSERT_EQ(a->size(), b->size());
  ASSERT_EQ(a->size(), c->size());
  bool identical = true;
  bool any_different = false;
  for (std::size_t i = 0; i < a->size(); ++i) {
    identical = identical && (*a)[i].getVector3fMap() == (*b)[i].getVector3fMap();
    any_different = any_different || (*a)[i].getVector3fMap() != (*c)[i].getVector3fMap();
  }
  EXPECT_TRUE(identical);
  EXPECT_TRUE(any_different);
}

TEST(DepthCamera, OrganizedScanHasNaNsAndLabels) {
  const pcl::PolygonMesh mesh = makeAmicelly();
  SceneObject object;
  object.mesh = &mesh;
  object.pose = knownBoxPose();
  object.rgb = Eigen::Vector3f(1.0f, 0.0f, 0.0f);
  object.label = 7;
  CameraIntrinsics intrinsics;
  const Scan scan = renderScan({object}, intrinsics, ScanNoise());
  ASSERT_TRUE(scan.cloud);
  EXPECT_EQ(scan.cloud->width, 640u);
  EXPECT_EQ(scan.cloud->height, 480u);
  EXPECT_FALSE(scan.cloud->is_dense);
  EXPECT_TRUE(scan.cloud->sensor_origin_.isZero());
  ASSERT_EQ(scan.labels.size(), scan.cloud->size());
  std::size_t hits = 0;
  for (std::size_t i = 0; i < scan.labels.size(); ++i) {
    const auto& p = (*scan.cloud)[i];
    if (scan.labels[i] == 7) {
      ++hits;
      EXPECT_TRUE(std::isfinite(p.z));
      EXPECT_EQ(p.r, 255);
      EXPECT_EQ(p.g, 0);
    } else {
      EXPECT_EQ(scan.labels[i], -1);
      EXPECT_TRUE(std::isnan(p.x) && std::isnan(p.y) && std::isnan(p.z));
    }
  }
  EXPECT_GT(hits, 1000u);
  EXPECT_EQ(extractLabelCloud(scan, 7)->size(), hits);
  // Organized layout: the pixel (u, v) = (320, 240) looks along the optical axis.
  const Eigen::Isometry3d pose = makePose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 1.0));
  object.pose = pose;
  const Scan centred = renderScan({object}, intrinsics, ScanNoise::none());
  const auto& centre = centred.cloud->at(320, 240);
  EXPECT_NEAR(centre.z, 1.0, 0.07);
  EXPECT_NEAR(centre.x, centre.z * (320 - 319.5) / 525.0, 1e-6);
  EXPECT_NEAR(centre.y, centre.z * (240 - 239.5) / 525.0, 1e-6);
}

TEST(DepthCamera, TabletopScene) {
  std::vector<SyntheticModel> objects = {thesisModel("YellowRoundSalt"), thesisModel("EisKaffe"),
                                         thesisModel("Amicelly")};
  const std::vector<Eigen::Vector3d> placements = {Eigen::Vector3d(-0.2, 0.0, 0.3),
                                                   Eigen::Vector3d(0.0, 0.1, 0.0),
                                                   Eigen::Vector3d(0.2, -0.05, 1.0)};
  const auto start = std::chrono::steady_clock::now();
  const TabletopScene scene =
      makeTabletopScene(objects, placements, CameraIntrinsics(), ScanNoise::none());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "[ info     ] 640x480 table-top scene with 3 objects rendered in " << seconds * 1e3
            << " ms" << std::endl;
  EXPECT_LT(seconds, 5.0);  // generous: also holds for unoptimised builds on a loaded machine

  ASSERT_EQ(scene.poses.size(), 3u);
  EXPECT_EQ(scene.names[1], "EisKaffe");
  EXPECT_NEAR(scene.table_plane.head<3>().norm(), 1.0, 1e-6);
  EXPECT_NEAR(scene.table_plane.w(), 0.6, 1e-6);  // camera height

  const auto table = extractLabelCloud(scene.scan, 0);
  EXPECT_GT(table->size(), 50000u);
  for (const auto& p : *table) {
    EXPECT_NEAR(scene.table_plane.head<3>().dot(p.getVector3fMap()) + scene.table_plane.w(), 0.0,
                1e-5);
  }
  for (std::size_t i = 0; i < objects.size(); ++i) {
    SCOPED_TRACE(objects[i].name);
    const auto points = extractLabelCloud(scene.scan, static_cast<int>(i) + 1);
    EXPECT_GT(points->size(), 500u);
    const Eigen::AlignedBox3d box = boundingBox(objects[i].mesh);
    const Eigen::Isometry3d camera_to_model = scene.poses[i].inverse();
    for (const auto& p : *points) {
      const Eigen::Vector3d q = camera_to_model * p.getVector3fMap().cast<double>();
      EXPECT_TRUE((q.array() >= box.min().array() - 1e-4).all() &&
                  (q.array() <= box.max().array() + 1e-4).all());
      // Points above the table.
      EXPECT_GT(scene.table_plane.head<3>().dot(p.getVector3fMap()) + scene.table_plane.w(), -1e-5);
    }
    // The object stands upright on the table: its lowest vertex is on the plane and its z axis is
    // the plane normal.
    double lowest = 1e9;
    for (const auto& v : meshVertices(objects[i].mesh)) {
      const Eigen::Vector3d c = scene.poses[i] * v;
      lowest = std::min(lowest, scene.table_plane.head<3>().cast<double>().dot(c) +
                                    static_cast<double>(scene.table_plane.w()));
    }
    EXPECT_NEAR(lowest, 0.0, 1e-6);
    EXPECT_NEAR(
        angleBetweenDeg(scene.poses[i].linear().col(2), scene.table_plane.head<3>().cast<double>()),
        0.0, 1e-3);
  }

  // Noise keeps the labels (same geometry) and is reproducible.
  const TabletopScene noisy1 =
      makeTabletopScene(objects, placements, CameraIntrinsics(), ScanNoise());
  const TabletopScene noisy2 =
      makeTabletopScene(objects, placements, CameraIntrinsics(), ScanNoise());
  EXPECT_EQ(noisy1.scan.labels, scene.scan.labels);
  for (std::size_t i = 0; i < noisy1.scan.cloud->size(); i += 97) {
    const auto& a = (*noisy1.scan.cloud)[i];
    const auto& b = (*noisy2.scan.cloud)[i];
    if (std::isfinite(a.z)) {
      EXPECT_EQ(a.getVector3fMap(), b.getVector3fMap());
    }
  }
}

// Edge artefacts against a scene with one known depth edge: a wall at 1 m, a 20 cm box centred
// at 0.8 m (its front face at 0.7 m). Oracle: the pixels whose 4-neighbours differ by more than
// edge_step are the box's outline (computed here from the noise-free render); only they may change,
// every one of them is either dropped (NaN), a flying pixel between the two depths on its own ray,
// or untouched; with dropout 1 all of them are NaN.
TEST(DepthCamera, EdgeArtefactsOnlyAlongDepthEdges) {
  const pcl::PolygonMesh wall = makePlane(3.0, 3.0), box = makeBox(0.2, 0.2, 0.2);
  SceneObject w, b;
  w.mesh = &wall;
  w.pose = Eigen::Translation3d(0.0, 0.0, 1.0) * Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX());
  b.mesh = &box;
  b.pose = Eigen::Translation3d(0.0, 0.0, 0.8);
  b.label = 1;
  const CameraIntrinsics k;
  const Scan clean = renderScan({w, b}, k, ScanNoise::none());
  const auto& c = *clean.cloud;
  std::vector<bool> edge(c.size(), false);
  std::size_t edges = 0;
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * k.width + u;
      const int du[4] = {-1, 1, 0, 0}, dv[4] = {0, 0, -1, 1};
      for (int n = 0; n < 4; ++n) {
        const int nu = u + du[n], nv = v + dv[n];
        if (nu >= 0 && nv >= 0 && nu < k.width && nv < k.height &&
            std::abs(c[static_cast<std::size_t>(nv) * k.width + nu].z - c[i].z) > 0.03f)
          edge[i] = true;
      }
      edges += edge[i];
    }
  ASSERT_GT(edges, 400u);  // the box's outline on both sides of the step
  EdgeArtefacts a;
  a.seed = 7;
  Scan scan = clean;
  scan.cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZRGB>>(*clean.cloud);
  addEdgeArtefacts(scan, a);
  std::size_t dropped = 0, flying = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const auto& p = (*scan.cloud)[i];
    if (!edge[i]) {
      EXPECT_EQ(p.getVector3fMap(), c[i].getVector3fMap()) << "pixel " << i;
      continue;
    }
    if (!std::isfinite(p.z)) {
      ++dropped;
      continue;
    }
    if (p.z != c[i].z) {
      ++flying;
      EXPECT_GT(p.z, 0.7f - 1e-4f);  // between the box's front face (0.7 m) and the wall
      EXPECT_LT(p.z, 1.0f + 1e-4f);
      EXPECT_NEAR(p.getVector3fMap().normalized().dot(c[i].getVector3fMap().normalized()), 1.f,
                  1e-6f)
          << "a flying pixel stays on its ray";
    }
  }
  // Binomial counts: dropout 0.5 of the edges, flying 0.3 of the rest; 6 standard deviations.
  const double n = static_cast<double>(edges);
  EXPECT_NEAR(static_cast<double>(dropped), 0.5 * n, 6.0 * std::sqrt(0.25 * n));
  EXPECT_NEAR(static_cast<double>(flying), 0.15 * n, 6.0 * std::sqrt(0.1275 * n));
  a.dropout = 1.0;
  Scan all = clean;
  all.cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZRGB>>(*clean.cloud);
  addEdgeArtefacts(all, a);
  for (std::size_t i = 0; i < c.size(); ++i)
    EXPECT_EQ(std::isfinite((*all.cloud)[i].z), !edge[i]) << "pixel " << i;
}

// The share of an object inside the image against the pinhole's geometry: a 2 mm thin 20 cm
// square at 0.9 m, fronto-parallel, projects to a 116.7-pixel square. Centred on the image's
// right border (u = 639.5) half of it lies inside; on the corner, a quarter; in the middle,
// all; 1 m to the side (u = 902), none. Tolerance 0.02: one pixel column of 117 (0.9%) and the
// thin side faces, under a pixel.
TEST(DepthCamera, InViewShareCountsThePartBeyondTheBorder) {
  const pcl::PolygonMesh tile = makeBox(0.2, 0.2, 0.002);
  const CameraIntrinsics k;
  const double z = 0.9, border_u = (k.width - 0.5 - k.cx) * z / k.fx,
               border_v = (k.height - 0.5 - k.cy) * z / k.fy;
  SceneObject o;
  o.mesh = &tile;
  o.pose = Eigen::Translation3d(0.0, 0.0, z);
  EXPECT_DOUBLE_EQ(inViewShare(o, k), 1.0);
  o.pose = Eigen::Translation3d(border_u, 0.0, z);
  EXPECT_NEAR(inViewShare(o, k), 0.5, 0.02);
  o.pose = Eigen::Translation3d(border_u, border_v, z);
  EXPECT_NEAR(inViewShare(o, k), 0.25, 0.02);
  o.pose = Eigen::Translation3d(1.0, 0.0, z);
  EXPECT_DOUBLE_EQ(inViewShare(o, k), 0.0);
  // Without a pad nothing lies beyond the border: the share of what is drawn is all of it.
  o.pose = Eigen::Translation3d(border_u, 0.0, z);
  EXPECT_DOUBLE_EQ(inViewShare(o, k, 0), 1.0);
  EXPECT_THROW(inViewShare(o, k, -1), std::invalid_argument);
}

// A cluttered desk against what its spec promises: the object count, the target's visible
// share (recounted from the labels and a render of the target alone), the target absent from
// the twin (and only the target's pixels changed there, up to noise and the edges), every
// object on the desk, a box's top or the shelf; same seed, same scene.
TEST(SyntheticClutter, DeskMeetsItsSpec) {
  std::vector<SyntheticModel> distractors;
  for (const char* name : {"EisKaffe", "YellowRoundSalt", "Amicelly", "Cup", "Statue"})
    distractors.push_back(thesisModel(name));
  const SyntheticModel target = thesisModel("Box5");
  const ClutterSpec spec;
  int stacked = 0, background = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const ClutterScene scene = makeClutterScene(target, distractors, seed, spec);
    ASSERT_EQ(scene.names.front(), "Box5");
    ASSERT_EQ(scene.poses.size(), scene.names.size());
    int on_desk = 0;
    for (std::size_t i = 0; i < scene.names.size(); ++i) {
      on_desk += !scene.background[i];
      stacked += scene.stacked[i];
      background += scene.background[i];
      if (i > 0) {
        EXPECT_NE(scene.names[i], "Box5") << "the target's model is not a distractor";
      }
    }
    EXPECT_LE(on_desk, spec.max_objects);
    EXPECT_GE(on_desk, 3) << "seed " << seed;  // placement may fail for some, not most
    EXPECT_GE(scene.target_visible, spec.min_target_visible);
    EXPECT_LE(scene.target_visible, 1.0);
    SceneObject alone;
    alone.mesh = &target.mesh;
    alone.pose = scene.poses[0];
    EXPECT_DOUBLE_EQ(visibleShare(scene.present, 1, alone, CameraIntrinsics()),
                     scene.target_visible);
    EXPECT_DOUBLE_EQ(inViewShare(alone, CameraIntrinsics()), scene.target_in_view);
    EXPECT_GT(scene.target_in_view, 0.0) << "part of the target is seen";
    EXPECT_LE(scene.wholeTargetVisible(), scene.target_visible);
    EXPECT_EQ(std::count(scene.absent.labels.begin(), scene.absent.labels.end(), 1), 0);
    EXPECT_GT(std::count(scene.present.labels.begin(), scene.present.labels.end(), 1), 0);
    // The target's model frame: it stands upright, its z axis the desk's normal.
    const Eigen::Vector3d up = scene.poses[0].linear() * Eigen::Vector3d::UnitZ();
    EXPECT_NEAR(up.dot(scene.desk_plane.head<3>().cast<double>()), 1.0, 1e-6);  // a float plane
    const double height =
        scene.desk_plane.head<3>().cast<double>().dot(scene.poses[0].translation()) +
        scene.desk_plane[3];
    EXPECT_GE(height, -0.001) << "the target stands on the desk or on an object, not below";
  }
  EXPECT_GT(stacked, 0) << "6 desks of 10-25 objects stack something";
  EXPECT_GT(background, 6) << "2-5 shelf objects per desk";
  const ClutterScene a = makeClutterScene(target, distractors, 3, spec);
  const ClutterScene b = makeClutterScene(target, distractors, 3, spec);
  ASSERT_EQ(a.present.cloud->size(), b.present.cloud->size());
  for (std::size_t i = 0; i < a.present.cloud->size(); ++i) {
    const auto &p = (*a.present.cloud)[i], &q = (*b.present.cloud)[i];
    ASSERT_TRUE((!std::isfinite(p.z) && !std::isfinite(q.z)) || p.z == q.z) << i;
  }
  EXPECT_THROW(makeClutterScene(target, {}, 1, spec), std::invalid_argument);
  // A desk written as numbers: its recorded layout and view render the same frames, bit for bit.
  const ClutterScene c = renderClutterDesk(a.layout, a.view);
  EXPECT_EQ(c.names, a.names);
  EXPECT_EQ(c.target_visible, a.target_visible);
  EXPECT_EQ(c.target_in_view, a.target_in_view);
  for (const auto& [drawn, written] :
       {std::pair(&a.present, &c.present), std::pair(&a.absent, &c.absent)}) {
    ASSERT_EQ(written->cloud->size(), drawn->cloud->size());
    EXPECT_EQ(written->labels, drawn->labels);
    for (std::size_t i = 0; i < drawn->cloud->size(); ++i) {
      const auto &p = (*drawn->cloud)[i], &q = (*written->cloud)[i];
      ASSERT_TRUE((!std::isfinite(p.z) && !std::isfinite(q.z)) || p.z == q.z) << i;
    }
  }
  EXPECT_THROW(renderClutterDesk({}, a.view), std::invalid_argument);
  EXPECT_THROW(renderClutterDesk({DeskObject()}, a.view), std::invalid_argument);
}

TEST(DepthCamera, InvalidArguments) {
  const pcl::PolygonMesh mesh = makeBox5();
  CameraIntrinsics bad;
  bad.width = 0;
  EXPECT_THROW(renderCluster(mesh, knownBoxPose(), bad, ScanNoise()), std::invalid_argument);
  ScanNoise bad_noise;
  bad_noise.outlier_ratio = 1.5;
  EXPECT_THROW(renderCluster(mesh, knownBoxPose(), CameraIntrinsics(), bad_noise),
               std::invalid_argument);
  EXPECT_THROW(renderScan({SceneObject()}, CameraIntrinsics(), ScanNoise()), std::invalid_argument);
  EXPECT_THROW(makeTabletopScene({thesisModel("Box5")}, {}, CameraIntrinsics(), ScanNoise()),
               std::invalid_argument);
}

}  // namespace

namespace {

// Structured-light quantisation (ScanNoise::focal_baseline): a wall face-on at 1.23 m with no
// other noise. Oracle: every depth is focal_baseline / (k x disparity_step) for an integer k
// (to float rounding, 1e-6 relative), the one nearest the true depth (within half a step of
// z^2 disparity_step / focal_baseline, 2.9 mm x 1.23^2 / 2 = 2.2 mm).
TEST(DepthCamera, StructuredLightDepthsLieOnTheDisparityGrid) {
  const pcl::PolygonMesh wall = meshOf(
      {{-2, -2, 1.23f}, {2, -2, 1.23f}, {2, 2, 1.23f}, {-2, 2, 1.23f}}, {{0, 1, 2}, {0, 2, 3}});
  SceneObject object;
  object.mesh = &wall;
  ScanNoise noise = ScanNoise::none();
  noise.focal_baseline = 580.0 * 0.075;
  noise.disparity_step = 0.125;
  const Scan scan = renderScan({object}, CameraIntrinsics(), noise);
  const double step = 1.23 * 1.23 * noise.disparity_step / noise.focal_baseline;
  std::size_t seen = 0;
  for (const auto& p : *scan.cloud) {
    if (!std::isfinite(p.z))
      continue;
    ++seen;
    const double k = noise.focal_baseline / (p.z * noise.disparity_step);
    ASSERT_NEAR(k, std::round(k), 1e-6 * k) << "depth " << p.z << " is off the grid";
    ASSERT_LE(std::abs(p.z - 1.23), 0.5 * step + 1e-6);
  }
  EXPECT_GT(seen, 100000u);
}

}  // namespace
