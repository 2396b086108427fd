// The hostile-input table of doc/HOSTILE_INPUTS.md as tests: broken files, lying
// headers, NaN, Inf and 1e30 coordinates, degenerate clouds and meshes, wrong units, a scene
// without a table. Each gives a clear error (exception type and a fragment of its message) or
// a correct answer, never a crash or a hang, and a lying header does not allocate what it
// claims (checked in a forked child under an address-space limit).
#include "synthetic/depth_camera.h"
#include "synthetic/mesh_geometry.h"
#include "synthetic/pose_error.h"
#include "synthetic/synthetic_models.h"
#include "test_paths.h"

#include <pcl/common/transforms.h>
#include <pcl/conversions.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/io/scene_io.h>
#include <pcl/icf/localization/object_localizer.h>
#include <pcl/icf/registration/closest_face_query.h>
#include <pcl/icf/registration/estimate_pose.h>
#include <pcl/icf/registration/face_mesh.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>

namespace {

namespace fs = std::filesystem;
using pcl::icf::FaceMesh, pcl::icf::IcfModel, pcl::icf::IcfParams, pcl::icf::IcfResult,
    pcl::icf::IcfStatus, pcl::icf::InvalidMeshError;
using pcl::icf::io::EmptyCloudError, pcl::icf::io::FileError, pcl::icf::io::loadPolygonMesh,
    pcl::icf::io::loadSceneCloud;
using pcl::icf::localization::LocalizationStatus, pcl::icf::localization::LocalizerParams;
namespace synthetic = pcl::icf::synthetic;

/** The tests run under ASan/UBSan too (PCL_ICF_SANITIZED=1): the address-space limit is then
 * left out (the sanitizer reserves terabytes of shadow memory) and the big mesh is smaller. */
bool sanitized() {
  const char* v = std::getenv("PCL_ICF_SANITIZED");
  return v && std::string(v) == "1";
}

/** Runs \a f and expects an exception of type E whose message contains \a fragment. */
template <typename E>
void expectError(const std::function<void()>& f, const std::string& fragment) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected one containing '" << fragment << "'";
  } catch (const E& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos)
        << "message: " << e.what() << "\nexpected fragment: " << fragment;
  }
}

/** Runs \a load in a forked child whose address space may grow by at most 256 MB (unless
 * sanitized) and which is killed after 30 s: it must throw a FileError containing \a fragment.
 * A lying header that allocates what it claims dies of std::bad_alloc there instead. */
void expectBoundedFileError(const std::function<void()>& load, const std::string& fragment) {
  std::fflush(nullptr);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::alarm(30);
    if (!sanitized()) {
      std::ifstream statm("/proc/self/statm");
      long pages = 0;
      statm >> pages;
      const rlim_t limit = static_cast<rlim_t>(pages) * ::sysconf(_SC_PAGESIZE) + (256u << 20);
      const rlimit r{limit, limit};
      ::setrlimit(RLIMIT_AS, &r);
    }
    int code = 4;  // no exception
    try {
      load();
    } catch (const FileError& e) {
      code = std::string(e.what()).find(fragment) != std::string::npos ? 0 : 1;
      if (code)
        std::fprintf(stderr, "message: %s\n", e.what());
    } catch (const std::bad_alloc&) {
      code = 2;
    } catch (...) {
      code = 3;
    }
    std::_Exit(code);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << WTERMSIG(status)
                                 << " (14: the 30 s alarm, a hang)";
  const char* what[] = {"ok", "a FileError without the fragment", "std::bad_alloc: it allocated",
                        "another exception", "no exception"};
  EXPECT_EQ(WEXITSTATUS(status), 0)
      << what[std::min(WEXITSTATUS(status), 4)] << "; expected '" << fragment << "'";
}

class HostileInput : public pcl_icf_test::TempDirTest {
 protected:
  HostileInput() : TempDirTest("pcl_icf_hostile") {}
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& content) const {
    std::ofstream(path(name), std::ios::binary) << content;
    return path(name);
  }
  std::string cut(const std::string& source, const std::string& name, double keep) const {
    std::ifstream in(source, std::ios::binary);
    const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return write(name, all.substr(0, static_cast<std::size_t>(keep * all.size())));
  }
};

/** Box5 seen from 0.8 m at a fixed oblique pose, with the simulator's noise and outliers. */
struct View {
  synthetic::SyntheticModel model = synthetic::thesisModel("Box5");
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3f> points;
};

View boxView() {
  View v;
  v.truth.translate(Eigen::Vector3d(0.03, -0.02, 0.8));
  v.truth.rotate(Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 0.4, 0.2).normalized()));
  synthetic::ScanNoise noise;
  noise.seed = 5;
  const auto cloud =
      synthetic::renderCluster(v.model.mesh, v.truth, synthetic::CameraIntrinsics(), noise);
  for (const auto& p : *cloud)
    v.points.push_back(p.getVector3fMap());
  return v;
}

/** Within 5 mm and 3 degrees of the truth (symmetry-aware). */
void expectCorrectPose(const IcfResult& r, const View& v) {
  ASSERT_EQ(r.status, IcfStatus::Accepted) << pcl::icf::toString(r.status);
  const auto e = synthetic::poseError(Eigen::Isometry3d(r.object_pose.cast<double>()), v.truth,
                                      v.model.symmetry);
  EXPECT_LE(e.translation, 0.005);
  EXPECT_LE(e.rotation_deg, 3.0);
}

IcfResult estimate(const IcfModel& model, const std::vector<Eigen::Vector3f>& points) {
  IcfParams params;
  params.fallback = pcl::icf::FallbackPolicy::Off;
  return pcl::icf::estimatePose(model, points, Eigen::Vector3f::Zero(), params);
}

const IcfModel& boxModel() {
  static const IcfModel::ConstPtr model = IcfModel::build(synthetic::makeBox5());
  return *model;
}

using pcl::icf::synthetic::meshOf;

// ---- Files ------------------------------------------------------------------------------

TEST_F(HostileInput, TruncatedPcdAndPlyFiles) {
  pcl::PointCloud<pcl::PointXYZRGB> cloud;
  for (int i = 0; i < 200; ++i)
    cloud.push_back(pcl::PointXYZRGB(0.01f * i, 0.f, 1.f, 10, 20, 30));
  pcl::PCDWriter writer;
  writer.writeBinary(path("bin.pcd"), cloud);
  writer.writeBinaryCompressed(path("zip.pcd"), cloud);
  writer.writeASCII(path("txt.pcd"), cloud);
  pcl::io::savePLYFileBinary(path("bin.ply"), cloud);
  pcl::io::savePLYFileASCII(path("txt.ply"), cloud);
  for (double keep : {0.02, 0.5, 0.97}) {
    SCOPED_TRACE(keep);
    // Binary data cut short: a FileError that says so.
    expectError<FileError>([&] { loadSceneCloud(cut(path("bin.pcd"), "b.pcd", keep)); },
                           keep < 0.1 ? "DATA" : "truncated");
    expectError<FileError>([&] { loadSceneCloud(cut(path("zip.pcd"), "z.pcd", keep)); },
                           keep < 0.1 ? "DATA" : "truncated");
    expectError<FileError>([&] { loadSceneCloud(cut(path("bin.ply"), "b.ply", keep)); },
                           keep < 0.1 ? "end_header" : "truncated");
    expectError<FileError>([&] { loadSceneCloud(cut(path("txt.ply"), "t.ply", keep)); },
                           keep < 0.1 ? "end_header" : "truncated");
    // PCL's ascii PCD reader: a FileError, never a cloud padded to the header's POINTS.
    try {
      const auto loaded = loadSceneCloud(cut(path("txt.pcd"), "t.pcd", keep));
      ADD_FAILURE() << "a cut ascii PCD loaded " << loaded->size() << " points";
    } catch (const FileError& e) {
      SUCCEED() << e.what();
    }
  }
}

TEST_F(HostileInput, GarbagePcdPlyObjStl) {
  std::mt19937_64 rng(7);
  std::string garbage(4096, '\0');
  for (char& c : garbage)
    c = static_cast<char>(rng());
  expectError<FileError>([&] { loadSceneCloud(write("g.pcd", garbage)); }, "PCD");
  expectError<FileError>([&] { loadSceneCloud(write("g.ply", garbage)); }, "not a PLY file");
  expectError<FileError>([&] { loadPolygonMesh(write("g.ply", garbage)); }, "not a PLY file");
  expectError<FileError>([&] { loadPolygonMesh(write("g.obj", garbage)); }, "no vertices");
  expectError<FileError>([&] { loadPolygonMesh(write("g.stl", garbage)); }, "claims");
  // Text that looks right at first: a header line of control bytes, a PLY property out of
  // place, an OBJ face of letters, an ascii STL facet of two vertices.
  expectError<FileError>(
      [&] {
        loadSceneCloud(write("c.pcd", std::string("# .PCD v0.7\nVERSION 0.7\nFIELDS \x01\x02 y "
                                                  "z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                                                  "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n"
                                                  "1 2 3\n")));
      },
      "not printable");
  // Control bytes are garbage, a UTF-8 comment is not.
  EXPECT_EQ(loadSceneCloud(write("u.pcd",
                                 "# .PCD v0.7 caf\xc3\xa9\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 "
                                 "4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\n"
                                 "DATA ascii\n1 2 3\n"))
                ->size(),
            1u);
  expectError<FileError>(
      [&] {
        loadPolygonMesh(write("p.ply",
                              "ply\nformat ascii 1.0\nproperty float x\n"
                              "element vertex 1\nend_header\n1\n"));
      },
      "before any element");
  expectError<FileError>(
      [&] { loadPolygonMesh(write("f.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf a b c\n")); },
      ":4: 'a' is not a face vertex");
  expectError<FileError>(
      [&] {
        loadPolygonMesh(write("two.stl",
                              "solid t\nfacet normal 0 0 1\nouter loop\n"
                              "vertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n"
                              "endsolid t\n"));
      },
      "a facet with 2 vertices");
}

TEST_F(HostileInput, HeadersClaimingBillionsAllocateNothing) {
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  const std::string pcd =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
      "COUNT 1 1 1\n";
  // PCD: points beyond the reader's limit; a compressed block that claims to unpack to more
  // than its points; binary data far shorter than its points.
  expectBoundedFileError(
      [&] {
        loadSceneCloud(write("w.pcd", pcd +
                                          "WIDTH 4000000000\nHEIGHT 1\nPOINTS 4000000000\n"
                                          "DATA binary\n" +
                                          std::string(64, '\0')));
      },
      "more than");
  expectBoundedFileError(
      [&] {
        std::string body(8, '\0');
        const std::uint32_t sizes[2] = {4, 4000000000u};
        std::memcpy(&body[0], sizes, 8);
        loadSceneCloud(write("z.pcd", pcd +
                                          "WIDTH 10\nHEIGHT 1\nPOINTS 10\n"
                                          "DATA binary_compressed\n" +
                                          body + "abcd"));
      },
      "unpacks to");
  expectBoundedFileError(
      [&] {
        loadSceneCloud(write("s.pcd", pcd +
                                          "WIDTH 40000000\nHEIGHT 1\nPOINTS 40000000\n"
                                          "DATA binary\n" +
                                          std::string(120, '\0')));
      },
      "truncated");
  // PLY: vertices and faces by the billion in a file of a few bytes.
  expectBoundedFileError(
      [&] {
        loadSceneCloud(write("v.ply",
                             "ply\nformat binary_little_endian 1.0\n"
                             "element vertex 4000000000\n" +
                                 xyz + "end_header\n"));
      },
      "more than");
  expectBoundedFileError(
      [&] {
        loadPolygonMesh(write("v.ply",
                              "ply\nformat binary_little_endian 1.0\n"
                              "element vertex 3000000000\n" +
                                  xyz + "end_header\n"));
      },
      "more than");
  expectBoundedFileError(
      [&] {
        loadPolygonMesh(write("f.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" + xyz +
                                           "element face 4000000000\nproperty list uchar int "
                                           "vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
                                           "3 0 1 2\n"));
      },
      "lying header");
  // A face whose list claims 4 billion indices.
  expectBoundedFileError(
      [&] {
        std::string body(3 * 12, '\0');
        body += std::string("\xff\xff\xff\xff", 4);
        loadPolygonMesh(write("l.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" +
                                           xyz +
                                           "element face 1\nproperty list uint int "
                                           "vertex_indices\nend_header\n" +
                                           body));
      },
      "truncated");
  // Binary STL: a triangle count of 4 billion in an 84-byte file.
  expectBoundedFileError(
      [&] {
        std::string stl(84, ' ');
        const std::uint32_t n = 4000000000u;
        std::memcpy(&stl[80], &n, 4);
        loadPolygonMesh(write("t.stl", stl));
      },
      "claims 4000000000 triangles");
}

TEST_F(HostileInput, NanAndInfCoordinates) {
  // A scene of nothing but NaN and Inf: EmptyCloudError, which is a FileError.
  expectError<EmptyCloudError>(
      [&] { loadSceneCloud(write("nan.xyz", "nan nan nan\ninf 0 1\n0 -inf 1\n")); },
      "NaN or infinite");
  pcl::icf::io::SceneFileInfo info;
  const auto cloud = loadSceneCloud(write("mixed.xyz", "0 0 1\nnan 0 1\n1e39 0 1\n0 1 1\n"), &info);
  EXPECT_EQ(info.points, 4u);
  EXPECT_EQ(info.finite_points, 2u) << "1e39 overflows float: not finite";
  EXPECT_FALSE(cloud->is_dense);

  // A cluster with NaN and Inf points among the good ones: they are left out, the pose is
  // right.
  View v = boxView();
  const std::size_t good = v.points.size();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (int i = 0; i < 50; ++i) {
    v.points.emplace_back(nan, 0.f, 0.8f);
    v.points.emplace_back(0.f, inf, 0.8f);
    v.points.emplace_back(-inf, nan, inf);
  }
  const IcfResult r = estimate(boxModel(), v.points);
  EXPECT_EQ(r.points, good);
  expectCorrectPose(r, v);

  // A mesh with a NaN vertex: the faces that use it are dropped and counted, the rest builds.
  pcl::PolygonMesh box = synthetic::makeBox5();
  pcl::PointCloud<pcl::PointXYZ> vertices;
  pcl::fromPCLPointCloud2(box.cloud, vertices);
  vertices[0].x = nan;
  pcl::toPCLPointCloud2(vertices, box.cloud);
  const FaceMesh mesh = FaceMesh::build(box);
  EXPECT_EQ(mesh.report().nonfinite_dropped, 1u);
  EXPECT_EQ(mesh.size(), 5u);
  // Every vertex NaN: a clear error.
  for (auto& p : vertices)
    p.x = nan;
  pcl::toPCLPointCloud2(vertices, box.cloud);
  expectError<InvalidMeshError>([&] { FaceMesh::build(box); }, "no usable face");
}

TEST_F(HostileInput, CoordinatesOf1e30) {
  // Stray points at 1e30 in a cluster are left out (beyond kMaxPointCoordinate): the pose
  // is right. Stray points at 1e5, within it, are outliers like any other.
  for (const float far : {1e30f, 1e5f}) {
    SCOPED_TRACE(far);
    View v = boxView();
    const std::size_t good = v.points.size();
    for (int i = 0; i < 20; ++i)
      v.points.emplace_back(far * (i % 2 ? 1.f : -1.f), far, far);
    const IcfResult r = estimate(boxModel(), v.points);
    EXPECT_EQ(r.points, far > pcl::icf::kMaxPointCoordinate ? good : good + 20);
    expectCorrectPose(r, v);
  }
  // A whole cluster at 1e30 m: nothing to find, no crash.
  std::vector<Eigen::Vector3f> far;
  for (const auto& p : boxView().points)
    far.push_back(p * 1e30f);
  const IcfResult r = estimate(boxModel(), far);
  EXPECT_NE(r.status, IcfStatus::Accepted);
  // A mesh whose faces are 1e30 wide: their areas overflow float, a clear error.
  expectError<InvalidMeshError>(
      [] {
        FaceMesh::build(
            meshOf({{0, 0, 0}, {1e30f, 0, 0}, {0, 1e30f, 0}, {1e30f, 1e30f, 0}}, {{0, 1, 3, 2}}));
      },
      "no usable face");
  // A model beside one vertex at 1e30 (unreferenced): the model is what the faces span.
  pcl::PolygonMesh box = synthetic::makeBox5();
  pcl::PointCloud<pcl::PointXYZ> vertices;
  pcl::fromPCLPointCloud2(box.cloud, vertices);
  vertices.push_back(pcl::PointXYZ(1e30f, 1e30f, 1e30f));
  pcl::toPCLPointCloud2(vertices, box.cloud);
  const FaceMesh mesh = FaceMesh::build(box);
  EXPECT_LT(mesh.boundsMax().maxCoeff(), 1.f);
  EXPECT_EQ(mesh.size(), 6u);
  // The same vertex used by an extra face: the box's faces are slivers next to it, a clear
  // error that says why.
  pcl::Vertices stray;
  stray.vertices = pcl::Indices{0, 1, static_cast<int>(vertices.size() - 1)};
  box.polygons.push_back(stray);
  expectError<InvalidMeshError>([&] { FaceMesh::build(box); }, "squared bounding-box diagonal");
  // A table-top scene with one pixel at 1e30 (a corrupt return) or at 1e5 (within
  // kMaxPointCoordinate, so it stays in): the first is left out like NaN, and the units check
  // measures the percentile extent, so neither makes the scene look like millimetres or spoils
  // the table; the box is found (5 mm / 3 degrees, as everywhere here).
  const synthetic::SyntheticModel box5 = synthetic::thesisModel("Box5");
  for (const float far : {1e30f, 1e5f}) {
    SCOPED_TRACE(far);
    synthetic::TabletopScene scene =
        synthetic::makeTabletopScene({box5}, {Eigen::Vector3d(0, 0, 0.3)},
                                     synthetic::CameraIntrinsics(), synthetic::ScanNoise::none());
    scene.scan.cloud->at(0).getVector3fMap() = Eigen::Vector3f::Constant(far);
    const auto found = pcl::icf::localization::localizeObject(*scene.scan.cloud, boxModel());
    ASSERT_EQ(found.status, LocalizationStatus::Found) << found.message;
    const auto e = synthetic::poseError(
        Eigen::Isometry3d(found.clusters[found.best].icf.object_pose.cast<double>()),
        scene.poses[0], box5.symmetry);
    EXPECT_LE(e.translation, 0.005);
    EXPECT_LE(e.rotation_deg, 3.0);
  }
}

TEST_F(HostileInput, ASinglePoint) {
  const auto cloud = loadSceneCloud(write("one.xyz", "0.1 0.2 0.9\n"));
  ASSERT_EQ(cloud->size(), 1u);
  const IcfResult r = estimate(boxModel(), {cloud->front().getVector3fMap()});
  EXPECT_EQ(r.status, IcfStatus::TooFewPoints);
  EXPECT_EQ(r.points, 1u);
  const auto found = pcl::icf::localization::localizeObject(*cloud, boxModel());
  EXPECT_EQ(found.status, LocalizationStatus::BadScene);
  EXPECT_NE(found.message.find("TooFewPoints"), std::string::npos) << found.message;
}

TEST_F(HostileInput, DuplicatePoints) {
  // Every point five times: the same object, the same answer.
  View v = boxView();
  std::vector<Eigen::Vector3f> five;
  for (const auto& p : v.points)
    five.insert(five.end(), 5, p);
  expectCorrectPose(estimate(boxModel(), five), v);
  // One point a thousand times: nothing to find, a finite pose, rejected.
  const IcfResult r = estimate(boxModel(), std::vector<Eigen::Vector3f>(1000, v.points[0]));
  EXPECT_EQ(r.status, IcfStatus::Rejected);
  EXPECT_TRUE(r.object_pose.allFinite());
}

TEST_F(HostileInput, FlatCluster) {
  // A 40 x 40 cm patch of a wall at 0.8 m, seen face on: larger than any face of the box, so
  // a box cannot explain it; the localizer (cluster as given) must not report it.
  pcl::PointCloud<pcl::PointXYZ> wall;
  for (int i = -100; i <= 100; ++i)
    for (int j = -100; j <= 100; ++j)
      wall.push_back(pcl::PointXYZ(0.002f * i, 0.002f * j, 0.8f));
  LocalizerParams params;
  params.segment = false;
  const auto found = pcl::icf::localization::localizeObject(wall, boxModel(), params);
  EXPECT_EQ(found.status, LocalizationStatus::NotFound) << found.message;
  // Every judged hypothesis rejected with its reason; none judged: the message says why.
  for (const auto& c : found.clusters)
    EXPECT_FALSE(c.reason.empty());
  if (found.clusters.empty()) {
    EXPECT_NE(found.message.find("no hypothesis"), std::string::npos) << found.message;
  }
}

TEST_F(HostileInput, AMeshOfOneFace) {
  // One triangle, 10 cm: it builds, and its own view is found with the points on the face.
  const pcl::PolygonMesh tri = meshOf({{0, 0, 0}, {0.1f, 0, 0}, {0, 0.07f, 0}}, {{0, 1, 2}});
  const FaceMesh faces = FaceMesh::build(tri);
  EXPECT_EQ(faces.size(), 1u);
  const IcfModel::ConstPtr model = IcfModel::build(tri);
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translate(Eigen::Vector3f(0.02f, 0.01f, 0.7f));
  pose.rotate(Eigen::AngleAxisf(0.4f, Eigen::Vector3f(1, 1, 0).normalized()));
  std::vector<Eigen::Vector3f> points;
  for (const auto& s : pcl::icf::sampleSurface(faces, 600, 3))
    points.push_back(pose * s.point);
  const IcfResult r = estimate(*model, points);
  ASSERT_TRUE(r.object_pose.allFinite());
  ASSERT_NE(r.status, IcfStatus::TooFewPoints);
  if (r.accepted()) {
    // Every point lies on the posed triangle's plane.
    const Eigen::Isometry3f est(r.object_pose);
    const Eigen::Vector3f n = est.linear() * faces.faces()[0].normal;
    const float offset = n.dot(est * faces.faceVertex(0, 0));
    for (const auto& p : points)
      EXPECT_LT(std::abs(n.dot(p) - offset), 0.002f);
  }
}

TEST_F(HostileInput, AMeshOfAMillionFaces) {
  // A 1000 x 500 grid of quads split into triangles, on a gentle wave: 1,000,000 faces (200,000
  // under the sanitizers, which are 10x slower). The faces, the exact index and a few queries
  // against brute force.
  const int nx = sanitized() ? 400 : 1000, ny = sanitized() ? 250 : 500;
  pcl::PointCloud<pcl::PointXYZ> grid;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      grid.push_back(pcl::PointXYZ(0.001f * i, 0.001f * j,
                                   0.005f * std::sin(0.02f * i) * std::cos(0.03f * j)));
  pcl::PolygonMesh mesh;
  pcl::toPCLPointCloud2(grid, mesh.cloud);
  mesh.polygons.reserve(2 * static_cast<std::size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      pcl::Vertices t1, t2;
      t1.vertices = pcl::Indices{a, b, d};
      t2.vertices = pcl::Indices{a, d, c};
      mesh.polygons.push_back(t1);
      mesh.polygons.push_back(t2);
    }
  const FaceMesh faces = FaceMesh::build(mesh);
  EXPECT_EQ(faces.size(), 2u * nx * ny);
  const pcl::icf::EmbreeClosestFaceIndex index(faces);
  const pcl::icf::BruteForceClosestFace brute(faces);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<float> u(-0.05f, 0.55f);
  for (int q = 0; q < 5; ++q) {
    const Eigen::Vector3f p(u(rng), u(rng), 0.5f * u(rng));
    EXPECT_NEAR(index.closestFace(p).distance, brute.closestFace(p).distance, 1e-6f);
  }
}

TEST_F(HostileInput, NonManifoldMeshAndFlippedNormals) {
  // Three triangles on one edge (a "book"), a dangling triangle touching it at a vertex, an
  // unused vertex: it builds, and the index agrees with brute force.
  const pcl::PolygonMesh book = meshOf({{0, 0, 0},
                                        {0, 0, 0.1f},
                                        {0.1f, 0, 0},
                                        {-0.1f, 0, 0},
                                        {0, 0.1f, 0},
                                        {0.1f, 0.1f, 0.1f},
                                        {0.2f, 0.2f, 0.2f},
                                        {5, 5, 5}},
                                       {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}, {1, 5, 6}});
  const FaceMesh faces = FaceMesh::build(book);
  EXPECT_EQ(faces.size(), 4u);
  const pcl::icf::EmbreeClosestFaceIndex index(faces);
  const pcl::icf::BruteForceClosestFace brute(faces);
  for (const Eigen::Vector3f& p :
       {Eigen::Vector3f(0.05f, 0.05f, 0.05f), Eigen::Vector3f(-0.2f, 0.3f, 0.01f),
        Eigen::Vector3f(0.3f, 0.1f, 0.2f)})
    EXPECT_NEAR(index.closestFace(p).distance, brute.closestFace(p).distance, 1e-6f);

  // Box5 with three of its six faces wound the wrong way (inward normals): the pose of its
  // view is still found.
  pcl::PolygonMesh flipped = synthetic::makeBox5();
  for (std::size_t f = 0; f < flipped.polygons.size(); f += 2)
    std::reverse(flipped.polygons[f].vertices.begin(), flipped.polygons[f].vertices.end());
  const IcfModel::ConstPtr model = IcfModel::build(flipped);
  const View v = boxView();
  expectCorrectPose(estimate(*model, v.points), v);
}

TEST_F(HostileInput, MillimetreDataWithMetreParameters) {
  // A table-top scene in millimetres, metre parameters: BadScene, saying why.
  const synthetic::SyntheticModel box = synthetic::thesisModel("Box5");
  synthetic::TabletopScene scene =
      synthetic::makeTabletopScene({box}, {Eigen::Vector3d(0, 0, 0.3)},
                                   synthetic::CameraIntrinsics(), synthetic::ScanNoise::none());
  pcl::PointCloud<pcl::PointXYZRGB> mm;
  pcl::transformPointCloud(*scene.scan.cloud, mm, Eigen::Affine3f(Eigen::Scaling(1000.f)));
  const auto found = pcl::icf::localization::localizeObject(mm, boxModel());
  EXPECT_EQ(found.status, LocalizationStatus::BadScene);
  EXPECT_NE(found.message.find("SceneUnitsSuspect"), std::string::npos) << found.message;
  // One cluster in millimetres against a metre model: not accepted.
  std::vector<Eigen::Vector3f> cluster;
  for (const auto& p : boxView().points)
    cluster.push_back(1000.f * p);
  EXPECT_NE(estimate(boxModel(), cluster).status, IcfStatus::Accepted);
  // A millimetre mesh with metre data: rejected as it is; right with FaceMeshOptions::scale.
  pcl::PolygonMesh box_mm = synthetic::makeBox(140, 90, 50);
  const View v = boxView();
  EXPECT_NE(estimate(*IcfModel::build(box_mm), v.points).status, IcfStatus::Accepted);
  pcl::icf::IcfModelParams scaled;
  scaled.mesh.scale = 1e-3f;
  expectCorrectPose(estimate(*IcfModel::build(box_mm, scaled), v.points), v);
}

TEST_F(HostileInput, ASceneWithNoTable) {
  // Box5 alone in front of the camera, nothing under it: no table, a status that says so; as
  // a given cluster (segment = false) it is found.
  const View v = boxView();
  const pcl::PolygonMesh& mesh = v.model.mesh;
  synthetic::SceneObject object;
  object.mesh = &mesh;
  object.pose = v.truth;
  const synthetic::Scan scan =
      synthetic::renderScan({object}, synthetic::CameraIntrinsics(), synthetic::ScanNoise());
  const auto found = pcl::icf::localization::localizeObject(*scan.cloud, boxModel());
  EXPECT_NE(found.status, LocalizationStatus::Found);
  EXPECT_FALSE(found.message.empty());
  LocalizerParams whole;
  whole.segment = false;
  const auto as_cluster = pcl::icf::localization::localizeObject(*scan.cloud, boxModel(), whole);
  ASSERT_EQ(as_cluster.status, LocalizationStatus::Found) << as_cluster.message;
  const auto e = synthetic::poseError(
      Eigen::Isometry3d(as_cluster.clusters[as_cluster.best].icf.object_pose.cast<double>()),
      v.truth, v.model.symmetry);
  EXPECT_LE(e.translation, 0.005);
  EXPECT_LE(e.rotation_deg, 3.0);
}

// Point pair voting's hostile inputs. A flat model (one triangle: every pair of it is
// coplanar, so it has no pair worth voting with) is searched for in the clusters instead and
// found on a table; a scene of isolated pixels (no surface normals), a scene that is one plane
// and a million-point unorganized cloud give a status with the reason, not a pose.
TEST_F(HostileInput, AFlatModelIsSearchedForInTheClusters) {
  const pcl::PolygonMesh tri = meshOf({{0, 0, 0}, {0.1f, 0, 0}, {0, 0.07f, 0}}, {{0, 1, 2}});
  const IcfModel::ConstPtr model = IcfModel::build(tri);
  EXPECT_EQ(model->pointPairs().pairs(), 0u);
  pcl::PointCloud<pcl::PointXYZ> wall;  // larger than the triangle: nothing explains it
  for (int i = -100; i <= 100; ++i)
    for (int j = -100; j <= 100; ++j)
      wall.push_back(pcl::PointXYZ(0.002f * i, 0.002f * j, 0.8f));
  LocalizerParams params;
  params.segment = false;
  const auto r = pcl::icf::localization::localizeObject(wall, *model, params);
  EXPECT_EQ(r.status, LocalizationStatus::NotFound) << r.message;
  for (const auto& c : r.clusters)
    EXPECT_EQ(c.source_cluster, 0) << "a hypothesis of the clusters' search";
  EXPECT_FALSE(r.message.empty());
}

TEST_F(HostileInput, ASceneOfIsolatedPixels) {
  // Every pixel at its own random depth in [0.5, 2] m: no two neighbours on one surface.
  pcl::PointCloud<pcl::PointXYZ> speckle(320, 240);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> depth(0.5f, 2.f);
  for (int v = 0; v < 240; ++v)
    for (int u = 0; u < 320; ++u) {
      const float z = depth(rng);
      speckle.at(u, v) = pcl::PointXYZ(z * (u - 159.5f) / 262.f, z * (v - 119.5f) / 262.f, z);
    }
  for (const bool segment : {true, false}) {
    LocalizerParams params;
    params.segment = segment;
    const auto r = pcl::icf::localization::localizeObject(speckle, boxModel(), params);
    EXPECT_NE(r.status, LocalizationStatus::Found) << r.message;
    EXPECT_FALSE(r.message.empty());
  }
}

TEST_F(HostileInput, AMillionPointUnorganizedCloud) {
  // 1,000,000 points (200,000 under the sanitizers) spread over a 1 m cube in front of the
  // camera: no surface anywhere. A status, in bounded memory (the test's own process).
  const std::size_t n = sanitized() ? 200000 : 1000000;
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.reserve(n);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  for (std::size_t i = 0; i < n; ++i)
    cloud.push_back(pcl::PointXYZ(u(rng), u(rng), 1.f + u(rng)));
  LocalizerParams params;
  params.segment = false;
  const auto r = pcl::icf::localization::localizeObject(cloud, boxModel(), params);
  EXPECT_NE(r.status, LocalizationStatus::Found) << r.message;
  EXPECT_FALSE(r.message.empty());
}

TEST_F(HostileInput, DoublePrecisionAndOutOfRangeMeshFiles) {
  // Vertices as doubles (MeshLab can write them): the same cube as with floats.
  const std::string cube =
      "element vertex 8\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 6\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  const FaceMesh mesh =
      FaceMesh::build(loadPolygonMesh(write("d.ply", "ply\nformat ascii 1.0\n" + cube)));
  EXPECT_NEAR(mesh.totalArea(), 6.0, 1e-6);
  // A list property inside the vertex element, of varying length (pcl::PLYReader asserted on
  // this): read past, the points are right.
  const auto listed = loadSceneCloud(write("l.ply",
                                           "ply\nformat ascii 1.0\nelement vertex 2\n"
                                           "property float x\nproperty list uchar "
                                           "float extra\nproperty float y\nproperty "
                                           "float z\nend_header\n1 0 2 3\n4 3 7 "
                                           "8 9 5 6\n"));
  ASSERT_EQ(listed->size(), 2u);
  EXPECT_EQ((*listed)[1].getVector3fMap(), Eigen::Vector3f(4, 5, 6));
  // A face index past the vertices: a FileError naming the face and the vertex.
  expectError<FileError>(
      [&] {
        loadPolygonMesh(write("o.ply",
                              "ply\nformat ascii 1.0\nelement vertex 3\n"
                              "property float x\nproperty float y\nproperty float z\n"
                              "element face 1\nproperty list uchar int vertex_indices\n"
                              "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"));
      },
      "face 0 refers to vertex 7, but the file has 3 vertices");
  expectError<FileError>(
      [&] { loadPolygonMesh(write("o.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")); },
      "face refers to vertex 9, but the file has 3 vertices");
  expectError<FileError>([&] { loadPolygonMesh(write("n.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n")); },
                         "refers before the first vertex");
}

}  // namespace
