// Mesh loaders on good files of every format and on missing, empty, garbage and truncated
// files: a FileError naming the file, never a crash.
#include "test_paths.h"

#include <pcl/conversions.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/registration/face_mesh.h>
#include <pcl/io/vtk_lib_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <vtkCellArray.h>
#include <vtkDataWriter.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataWriter.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace {

using pcl::icf::FaceMesh;
using pcl::icf::io::FileError;
using pcl::icf::io::loadPolygonMesh;

class MeshIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("pcl_icf_mesh_io_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& content) {
    const auto path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }
  std::string truncated(const std::string& source, const std::string& name, double keep) {
    std::ifstream in(source, std::ios::binary);
    const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return write(name, all.substr(0, static_cast<std::size_t>(keep * all.size())));
  }
  void expectFileError(const std::string& path, const std::string& fragment) {
    try {
      const auto mesh = loadPolygonMesh(path);
      // A reader may accept a damaged file partially; then the mesh must still be coherent
      // enough for FaceMesh to either build or throw its own clear error.
      FaceMesh::build(mesh);
      FAIL() << path << " loaded without error";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    } catch (const pcl::icf::InvalidMeshError& e) {
      SUCCEED() << e.what();
    }
  }
  std::filesystem::path dir_;
};

TEST_F(MeshIo, EveryFormatLoadsTheSameCube) {
  for (const char* name :
       {"box_quads.ply", "box_quads.obj", "box_triangles.stl", "box_quads.vtk"}) {
    SCOPED_TRACE(name);
    const auto mesh = FaceMesh::build(loadPolygonMesh(pcl_icf_test::fixture(name)));
    EXPECT_NEAR(mesh.totalArea(), 6.0, 1e-5);
    EXPECT_TRUE(mesh.boundsMax().isApprox(Eigen::Vector3f::Ones()));
    // Rectangles stay rectangles where the format keeps them.
    EXPECT_EQ(mesh.countFacesWithVertices(4),
              std::string(name).find("stl") == std::string::npos ? 6u : 0u);
  }
}

TEST_F(MeshIo, RealBinaryPlyAndRealObj) {
  PCL_ICF_REQUIRE_SHARED(cube, "pcl/cube.ply");
  EXPECT_EQ(FaceMesh::build(loadPolygonMesh(cube)).size(), 12u);
  PCL_ICF_REQUIRE_SHARED(can, "ycbv/010_potted_meat_can_textured.obj");
  const auto mesh = FaceMesh::build(loadPolygonMesh(can));
  EXPECT_EQ(mesh.size() + mesh.report().degenerate_dropped + mesh.report().duplicate_dropped,
            16384u);
}

TEST_F(MeshIo, MissingEmptyAndUnknownFilesThrow) {
  expectFileError((dir_ / "nope.ply").string(), "no such file");
  expectFileError(write("empty.ply", ""), "empty");
  expectFileError(write("mesh.xyz", "0 0 0\n"), "unknown mesh extension");
  expectFileError(dir_.string() + "/", "not a regular file");
}

TEST_F(MeshIo, GarbageFilesThrow) {
  const std::string garbage = "\x01\x02 this is not a mesh \xff\xfe\n1 2 3\n";
  expectFileError(write("garbage.ply", garbage), "PLY");
  expectFileError(write("garbage.obj", garbage), "");
  expectFileError(write("garbage.stl", garbage), "");
  expectFileError(write("garbage.vtk", garbage), "");
}

TEST_F(MeshIo, TruncatedFilesThrow) {
  for (const char* name :
       {"box_quads.ply", "box_quads.obj", "box_triangles.stl", "box_quads.vtk"}) {
    SCOPED_TRACE(name);
    // Cut inside the header and inside the vertex list.
    expectFileError(truncated(pcl_icf_test::fixture(name), std::string("h_") + name, 0.1), "");
    const std::string half = truncated(pcl_icf_test::fixture(name), std::string("v_") + name, 0.5);
    try {
      const auto mesh = FaceMesh::build(loadPolygonMesh(half));
      // A reader that keeps the complete faces before the cut gives a smaller, valid mesh.
      EXPECT_LT(mesh.totalArea(), 6.0 - 1e-3);
    } catch (const FileError&) {
    } catch (const pcl::icf::InvalidMeshError&) {
    }
  }
}

TEST_F(MeshIo, TruncatedBinaryPlyThrows) {
  PCL_ICF_REQUIRE_SHARED(cube, "pcl/cube.ply");
  for (double keep : {0.2, 0.6, 0.95})
    expectFileError(truncated(cube, "cut_" + std::to_string(keep) + ".ply", keep), "");
}

// The .vtk reader (io/src/vtk_reader.cpp) against VTK's own: the fixture as
// pcl::io::loadPolygonFileVTK reads it, and files written by vtkPolyDataWriter.
std::vector<float> vertexCoordinates(const pcl::PolygonMesh& mesh) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  pcl::fromPCLPointCloud2(mesh.cloud, cloud);
  std::vector<float> xyz;
  for (const auto& p : cloud.points)
    xyz.insert(xyz.end(), {p.x, p.y, p.z});
  return xyz;
}

std::vector<std::vector<pcl::index_t>> polygonIndices(const pcl::PolygonMesh& mesh) {
  std::vector<std::vector<pcl::index_t>> out;
  for (const auto& polygon : mesh.polygons)
    out.push_back(polygon.vertices);
  return out;
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST_F(MeshIo, VtkFixtureReadsAsVtkReadsIt) {
  const std::string path = pcl_icf_test::fixture("box_quads.vtk");
  pcl::PolygonMesh oracle;
  ASSERT_GE(pcl::io::loadPolygonFileVTK(path, oracle), 0);
  const pcl::PolygonMesh mesh = loadPolygonMesh(path);
  EXPECT_EQ(vertexCoordinates(mesh), vertexCoordinates(oracle));
  EXPECT_EQ(polygonIndices(mesh), polygonIndices(oracle));
  ASSERT_EQ(mesh.cloud.fields.size(), 3u);
  for (const auto& field : mesh.cloud.fields)
    EXPECT_EQ(field.datatype, pcl::PCLPointField::FLOAT32) << field.name;
}

TEST_F(MeshIo, VtkFuzzSeedsReadAsVtkReadsThem) {
  const std::filesystem::path seeds =
      std::filesystem::path(PCL_ICF_TEST_DATA) / ".." / ".." / "fuzz" / "corpus" / "fuzz_mesh_vtk";
  ASSERT_TRUE(std::filesystem::is_directory(seeds)) << seeds;
  for (const auto& entry : std::filesystem::directory_iterator(seeds)) {
    const std::string path = entry.path().string();
    SCOPED_TRACE(path);
    pcl::PolygonMesh oracle;
    ASSERT_GE(pcl::io::loadPolygonFileVTK(path, oracle), 0);
    const pcl::PolygonMesh mesh = loadPolygonMesh(path);
    EXPECT_EQ(vertexCoordinates(mesh), vertexCoordinates(oracle));
    // pcl::io::loadPolygonFileVTK keeps polygons only; ours adds the strips' triangles after.
    const auto faces = polygonIndices(mesh), oracle_faces = polygonIndices(oracle);
    ASSERT_FALSE(oracle_faces.empty());
    ASSERT_GE(faces.size(), oracle_faces.size());
    EXPECT_EQ(decltype(faces)(faces.begin(), faces.begin() + oracle_faces.size()), oracle_faces);
  }
}

TEST_F(MeshIo, VtkWrittenByVtkAsciiBinaryClassicAndNewLayout) {
  // Seven points: a quad, a triangle and a strip of five points (its second triangle wound
  // the other way), plus a line and a vertex cell, which are not faces.
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  const double xyz[7][3] = {{0, 0, 0},      {1, 0, 0},      {1, 1, 0},       {0, 1, 0},
                            {0.5, 0.25, 1}, {1e-3, 2.5, 3}, {-7, 1e5, 0.125}};
  for (const auto& p : xyz)
    points->InsertNextPoint(p);
  vtkNew<vtkCellArray> polys, strips, lines, verts;
  const vtkIdType quad[] = {0, 1, 2, 3}, triangle[] = {1, 4, 2}, strip[] = {0, 1, 5, 6, 4};
  const vtkIdType line[] = {3, 6}, vert[] = {5};
  polys->InsertNextCell(4, quad);
  polys->InsertNextCell(3, triangle);
  strips->InsertNextCell(5, strip);
  lines->InsertNextCell(2, line);
  verts->InsertNextCell(1, vert);
  vtkNew<vtkPolyData> data;
  data->SetPoints(points);
  data->SetPolys(polys);
  data->SetStrips(strips);
  data->SetLines(lines);
  data->SetVerts(verts);
  // Field data (written before POINTS, read past) and point data (after the cells, not read).
  vtkNew<vtkDoubleArray> field_doubles;
  field_doubles->SetName("scale");
  field_doubles->SetNumberOfComponents(2);
  for (int i = 0; i < 6; ++i)
    field_doubles->InsertNextValue(0.5 * i);
  vtkNew<vtkIntArray> field_ints;
  field_ints->SetName("ids");
  for (int i = 0; i < 4; ++i)
    field_ints->InsertNextValue(-i);
  data->GetFieldData()->AddArray(field_doubles);
  data->GetFieldData()->AddArray(field_ints);
  vtkNew<vtkFloatArray> scalars;
  scalars->SetName("s");
  for (int i = 0; i < 7; ++i)
    scalars->InsertNextValue(static_cast<float>(i));
  data->GetPointData()->SetScalars(scalars);

  // Oracle: the polydata's own points (as float) and cells; strips as VTK decomposes them.
  std::vector<float> expected_xyz;
  for (const auto& p : xyz)
    for (const double c : p)
      expected_xyz.push_back(static_cast<float>(c));
  const std::vector<std::vector<pcl::index_t>> expected_faces = {
      {0, 1, 2, 3}, {1, 4, 2}, {0, 1, 5}, {1, 6, 5}, {5, 6, 4}};

  for (const bool binary : {false, true})
    for (const int version : {vtkDataWriter::VTK_LEGACY_READER_VERSION_4_2,
                              vtkDataWriter::VTK_LEGACY_READER_VERSION_5_1}) {
      const std::string path =
          (dir_ / ((binary ? "binary_" : "ascii_") + std::to_string(version) + ".vtk")).string();
      SCOPED_TRACE(path);
      vtkNew<vtkPolyDataWriter> writer;
      writer->SetInputData(data);
      writer->SetFileName(path.c_str());
      writer->SetFileVersion(version);
      if (binary)
        writer->SetFileTypeToBinary();
      else
        writer->SetFileTypeToASCII();
      ASSERT_EQ(writer->Write(), 1);
      const std::string bytes = fileBytes(path);
      ASSERT_NE(bytes.find(version == 51 ? "OFFSETS" : "POLYGONS 2 9"), std::string::npos);
      ASSERT_LT(bytes.find("FIELD FieldData 2"), bytes.find("POINTS 7 double"))
          << bytes.substr(0, 400);
      const pcl::PolygonMesh mesh = loadPolygonMesh(path);
      EXPECT_EQ(vertexCoordinates(mesh), expected_xyz);
      EXPECT_EQ(polygonIndices(mesh), expected_faces);
      // Every cut of the file: a FileError (or a mesh FaceMesh judges), never a crash.
      for (std::size_t keep = 0; keep < bytes.size(); ++keep) {
        const std::string cut = write("cut.vtk", bytes.substr(0, keep));
        try {
          FaceMesh::build(loadPolygonMesh(cut));
        } catch (const FileError&) {
        } catch (const pcl::icf::InvalidMeshError&) {
        }
      }
    }
}

TEST_F(MeshIo, VtkCutAtEveryByteThrows) {
  const std::string bytes = fileBytes(pcl_icf_test::fixture("box_quads.vtk"));
  // Every cut before the last face's last index loses data: a FileError, or (a cut right
  // after the points, which is a valid file of points without faces) FaceMesh's "no usable
  // face"; never a crash, never a mesh.
  const std::size_t complete = bytes.find_last_of("0123456789") + 1;
  for (std::size_t keep = 0; keep + 1 < complete; ++keep) {
    SCOPED_TRACE(keep);
    expectFileError(write("cut.vtk", bytes.substr(0, keep)), "");
  }
  // The cut VTK's reader crashed on (SIGSEGV in vtkDataReader::ReadString): right after the
  // line "POLYGONS 6 30".
  const std::size_t polygons = bytes.find("POLYGONS 6 30\n") + 14;
  expectFileError(write("polygons_line.vtk", bytes.substr(0, polygons)),
                  ":14: POLYGONS claims 30 values, more than the rest of the file can hold");
}

TEST_F(MeshIo, VtkLyingCountsAndOtherDatasetsFailFast) {
  const std::string head = "# vtk DataFile Version 3.0\nlies\nASCII\nDATASET POLYDATA\n";
  expectFileError(write("points.vtk", head + "POINTS 4000000000 float\n0 0 0\n"),
                  "POINTS claims 4000000000 points, more than the 100000000");
  expectFileError(write("points_short.vtk", head + "POINTS 90000000 float\n0 0 0\n"),
                  "truncated file or a lying count");
  const std::string triangle = "POINTS 3 float\n0 0 0 1 0 0 0 1 0\n";
  expectFileError(write("cells.vtk", head + triangle + "POLYGONS 50000000 99999999\n3 0 1 2\n"),
                  "truncated file or a lying count");
  expectFileError(write("count.vtk", head + triangle + "POLYGONS 1 4\n4000000000 0 1 2\n"),
                  "POLYGONS cell 0 claims 4000000000 points");
  expectFileError(write("index.vtk", head + triangle + "POLYGONS 1 4\n3 0 1 7\n"),
                  ":7: POLYGONS cell 0 refers to point 7, but the file has 3 points");
  expectFileError(write("field.vtk", head + "FIELD FieldData 1\nbig 3 4000000000 float\n"),
                  "FIELD array big claims 3 x 4000000000 values");
  expectFileError(write("field_short.vtk", head + "FIELD FieldData 1\nf 3 1000 float\n1 2 3\n"),
                  "FIELD array f claims 3000 values, more than the rest of the file can hold");
  const std::string binary = "# vtk DataFile Version 3.0\nlies\nBINARY\nDATASET POLYDATA\n";
  expectFileError(write("binary.vtk", binary + "POINTS 3 double\n" + std::string(8, '\0')),
                  "POINTS claims 9 values of double, the file holds 1");
  // Found by fuzz_mesh_vtk: classic cells claiming more cells than their size holds, the file
  // ending right after those values. The count of the cell past the size was read beyond the
  // file (ASan: heap-buffer-overflow); now it is refused before it is read.
  const std::string be_ints = std::string("\0\0\0\2\0\0\0\0\0\0\0\1", 12);
  expectFileError(write("cells_past_size.vtk", binary + "POINTS 3 float\n" + std::string(36, '\0') +
                                                   "\nLINES 2 3\n" + be_ints),
                  "LINES claims 2 cells, its 3 values end at cell 1");
  expectFileError(
      write("grid.vtk", "# vtk DataFile Version 3.0\ng\nASCII\nDATASET UNSTRUCTURED_GRID\n"),
      "DATASET UNSTRUCTURED_GRID is not a polygon mesh");
  const std::string v51 = "# vtk DataFile Version 5.1\nlies\nASCII\nDATASET POLYDATA\n";
  expectFileError(write("offsets.vtk", v51 + triangle +
                                           "POLYGONS 2 3\nOFFSETS vtktypeint64\n0 4\n"
                                           "CONNECTIVITY vtktypeint64\n0 1 2\n"),
                  "OFFSETS value 1 is 4");
  // Attributes after the cells are not needed: reading stops there.
  const auto mesh = loadPolygonMesh(write(
      "attributes.vtk", head + triangle + "POLYGONS 1 4\n3 0 1 2\nPOINT_DATA 3\nSCALARS s \x01"));
  EXPECT_EQ(mesh.polygons.size(), 1u);
}

}  // namespace
