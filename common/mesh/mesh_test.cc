#include "common/mesh/mesh.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

class MeshTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::path(::testing::TempDir()) /
        ("mesh_test_" +
         std::string(
             ::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path Write(const std::string& name,
                              const std::string& content) {
    const std::filesystem::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }

  // The message of the uw::Error that reading `content` throws.
  std::string ReadError(const std::string& content) {
    const std::filesystem::path path = Write("bad.ply", content);
    try {
      ReadPly(path);
    } catch (const Error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(path.string()), std::string::npos) << message;
      return message;
    }
    ADD_FAILURE() << "no error reading:\n" << content;
    return "";
  }

  std::filesystem::path dir_;
};

template <typename T>
std::string Bytes(const T& value) {
  return std::string(reinterpret_cast<const char*>(&value), sizeof(T));
}

constexpr char kAsciiHeader[] =
    "ply\n"
    "format ascii 1.0\n"
    "element vertex 3\n"
    "property float x\n"
    "property float y\n"
    "property float z\n"
    "element face 1\n"
    "property list uchar int vertex_indices\n"
    "end_header\n";

TEST_F(MeshTest, TriangleNormalIsUnitAndCounterClockwise) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 1}, {2, 0, 1}, {0, 3, 1}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 1}};
  EXPECT_TRUE(mesh.TriangleNormal(0).isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(mesh.TriangleNormal(1).isApprox(-Eigen::Vector3d::UnitZ()));
}

TEST_F(MeshTest, BinaryRoundTripIsBitExact) {
  TriangleMesh mesh;
  // Values that a decimal round trip would perturb, and extremes.
  mesh.vertices = {{0.1, -0.2, 1.0 / 3.0},
                   {-0.0, 1e-310, std::numeric_limits<double>::max()},
                   {123456.789, -std::numeric_limits<double>::min(), M_PI},
                   {std::nextafter(1.0, 2.0), -1e300, 2.5e-8}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {3, 2, 1}};
  const std::filesystem::path path = dir_ / "sub" / "mesh.ply";
  WritePly(mesh, path, "a test's frame; units: none");

  const TriangleMesh read = ReadPly(path);
  ASSERT_EQ(read.vertices.size(), mesh.vertices.size());
  ASSERT_EQ(read.triangles.size(), mesh.triangles.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    EXPECT_EQ(std::memcmp(read.vertices[i].data(), mesh.vertices[i].data(),
                          3 * sizeof(double)),
              0)
        << "vertex " << i;
  }
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    EXPECT_EQ(read.triangles[i], mesh.triangles[i]);
  }
  // Header, 24 bytes per vertex and 13 per face; no temporary left.
  const std::string content = ReadFileToString(path);
  const size_t body = content.find("end_header\n") + 11;
  EXPECT_EQ(content.size() - body, 4 * 24 + 3 * 13);
  // The frame is stated in the header, as given.
  EXPECT_EQ(content.find("format binary_little_endian 1.0\ncomment a test's "
                         "frame; units: none\nelement vertex 4\n"),
            4u);
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry :
       std::filesystem::directory_iterator(path.parent_path())) {
    ++files;
  }
  EXPECT_EQ(files, 1u);
}

TEST_F(MeshTest, ReadsHandWrittenAscii) {
  // Float and extra vertex properties, comments, CRLF, a blank line, a quad
  // (split into two triangles) and a face element with an extra property.
  const std::string content =
      "ply\r\n"
      "format ascii 1.0\r\n"
      "comment made by hand\r\n"
      "element vertex 4\r\n"
      "property float x\r\n"
      "property float nx\r\n"
      "property float y\r\n"
      "property double z\r\n"
      "property uchar red\r\n"
      "element face 2\r\n"
      "property list uchar int vertex_indices\r\n"
      "property uchar flags\r\n"
      "end_header\r\n"
      "0 9 0 0 255\r\n"
      "1.5 9 0 0.25 0\r\n"
      "\r\n"
      "1.5 9 2 0.25 7\r\n"
      "0 9 2 -1e-3 8\r\n"
      "3 0 1 2 1\r\n"
      "4 0 1 2 3 0\r\n";
  const TriangleMesh mesh = ReadPly(Write("hand.ply", content));
  ASSERT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.vertices[1], Eigen::Vector3d(1.5, 0.0, 0.25));
  EXPECT_EQ(mesh.vertices[3], Eigen::Vector3d(0.0, 2.0, -1e-3));
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(mesh.triangles[0], Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(mesh.triangles[1], Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(mesh.triangles[2], Eigen::Vector3i(0, 2, 3));
}

TEST_F(MeshTest, ReadsBinaryFloatWithExtraPropertiesAndElements) {
  std::string content =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "element vertex 3\n"
      "property uchar red\n"
      "property float x\n"
      "property float y\n"
      "property float z\n"
      "property list uchar float texcoord\n"
      "element face 1\n"
      "property list int uint vertex_index\n"
      "element edge 1\n"
      "property int vertex1\n"
      "property int vertex2\n"
      "end_header\n";
  const float xyz[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0.5f}};
  for (const auto& vertex : xyz) {
    content += Bytes(uint8_t{9});
    for (const float value : vertex) content += Bytes(value);
    content += Bytes(uint8_t{2}) + Bytes(0.5f) + Bytes(0.25f);
  }
  content += Bytes(int32_t{3}) + Bytes(uint32_t{2}) + Bytes(uint32_t{1}) +
             Bytes(uint32_t{0});
  content += Bytes(int32_t{0}) + Bytes(int32_t{1});
  const TriangleMesh mesh = ReadPly(Write("float.ply", content));
  ASSERT_EQ(mesh.vertices.size(), 3u);
  EXPECT_EQ(mesh.vertices[2], Eigen::Vector3d(0.0, 1.0, 0.5));
  ASSERT_EQ(mesh.triangles.size(), 1u);
  EXPECT_EQ(mesh.triangles[0], Eigen::Vector3i(2, 1, 0));
}

TEST_F(MeshTest, RejectsMalformedHeaders) {
  EXPECT_NE(ReadError("solid stl\n").find(":1: not a PLY file"),
            std::string::npos);
  EXPECT_NE(ReadError("ply\nformat binary_big_endian 1.0\nend_header\n")
                .find(":2: unsupported format"),
            std::string::npos);
  EXPECT_NE(ReadError("ply\nformat ascii 1.0\nelement vertex -3\n")
                .find(":3: expected \"element <name> <count>\""),
            std::string::npos);
  EXPECT_NE(ReadError("ply\nformat ascii 1.0\nelement vertex 1\n"
                      "property quad x\n")
                .find(":4: unknown property type \"quad\""),
            std::string::npos);
  EXPECT_NE(ReadError("ply\nformat ascii 1.0\nelement vertex 1\n")
                .find("file ends inside the header"),
            std::string::npos);
  EXPECT_NE(ReadError("ply\nformat ascii 1.0\nelement vertex 1\n"
                      "property float x\nproperty float y\nend_header\n0 0\n")
                .find(":3: vertex element has no property z"),
            std::string::npos);
  EXPECT_NE(ReadError("ply\nformat ascii 1.0\nelement vertex 1\n"
                      "property int x\nproperty float y\nproperty float z\n"
                      "end_header\n0 0 0\n")
                .find("vertex property x must be float or double"),
            std::string::npos);
  EXPECT_NE(ReadError("ply\nformat ascii 1.0\nelement face 0\n"
                      "property list uchar int vertex_indices\nend_header\n")
                .find("no \"vertex\" element"),
            std::string::npos);
}

// A mesher's NaN vertex goes with its faces; the rest is renumbered.
TEST_F(MeshTest, DropsNonFiniteVerticesWithTheirFacesWhenAsked) {
  const std::string content =
      "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
      "property float y\nproperty float z\nelement face 3\n"
      "property list uchar int vertex_indices\nend_header\n"
      "0 0 0\nnan 0 0\n1 0 0\n0 1 0\n1 1 inf\n"
      "3 0 2 3\n3 0 1 2\n3 2 4 3\n";
  const std::filesystem::path path = Write("nan.ply", content);
  EXPECT_NE(ReadError(content).find("(vertex 1): non-finite vertex coordinate"),
            std::string::npos);
  size_t dropped = 0;
  const TriangleMesh mesh = ReadPlyDroppingNonFinite(path, &dropped);
  EXPECT_EQ(dropped, 2u);
  ASSERT_EQ(mesh.vertices.size(), 3u);
  EXPECT_EQ(mesh.vertices[1], Eigen::Vector3d(1, 0, 0));
  ASSERT_EQ(mesh.triangles.size(), 1u);
  EXPECT_EQ(mesh.triangles[0], Eigen::Vector3i(0, 1, 2));
  // A finite mesh reads as ReadPly reads it.
  const std::string finite =
      std::string(kAsciiHeader) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const TriangleMesh same =
      ReadPlyDroppingNonFinite(Write("finite.ply", finite), &dropped);
  EXPECT_EQ(dropped, 0u);
  EXPECT_EQ(same.vertices.size(), 3u);
  EXPECT_EQ(same.triangles.size(), 1u);
}

TEST_F(MeshTest, RejectsMalformedAsciiData) {
  const std::string header = kAsciiHeader;
  EXPECT_NE(ReadError(header + "0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n")
                .find("line 12 (vertex 2): non-finite vertex coordinate"),
            std::string::npos);
  EXPECT_NE(ReadError(header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n")
                .find("line 13 (face 0): vertex index 3 out of range "
                      "(3 vertices)"),
            std::string::npos);
  EXPECT_NE(ReadError(header + "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n")
                .find("vertex index -1 out of range"),
            std::string::npos);
  EXPECT_NE(ReadError(header + "0 0 0\n1 0 0\n0 1 0\n5 0 1 2 0 1\n")
                .find("face with 5 vertices"),
            std::string::npos);
  EXPECT_NE(ReadError(header + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n")
                .find("line 11 (vertex 1): bad number \"zero\""),
            std::string::npos);
  EXPECT_NE(ReadError(header + "0 0 0\n1 0\n0 1 0\n3 0 1 2\n")
                .find("line 11 (vertex 1): too few values"),
            std::string::npos);
  EXPECT_NE(ReadError(header + "0 0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
                .find("line 10 (vertex 0): 1 values more than the header"),
            std::string::npos);
  EXPECT_NE(ReadError(header + "0 0 0\n1 0 0\n0 1 0\n")
                .find("file ends before face 0 (header announces 1)"),
            std::string::npos);
  EXPECT_NE(ReadError(header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n")
                .find("line 14: data after the last element"),
            std::string::npos);
}

TEST_F(MeshTest, RejectsMalformedBinaryData) {
  const std::string header =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "element vertex 2\n"
      "property double x\n"
      "property double y\n"
      "property double z\n"
      "element face 1\n"
      "property list uchar int vertex_indices\n"
      "end_header\n";
  std::string vertices;
  for (const double value : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0}) {
    vertices += Bytes(value);
  }
  const std::string face = Bytes(uint8_t{3}) + Bytes(int32_t{0}) +
                           Bytes(int32_t{1}) + Bytes(int32_t{1});
  // Sanity: the well-formed file reads.
  EXPECT_EQ(
      ReadPly(Write("good.ply", header + vertices + face)).triangles.size(),
      1u);

  EXPECT_NE(ReadError(header + vertices + face.substr(0, 7))
                .find("file ends inside face 0"),
            std::string::npos);
  EXPECT_NE(ReadError(header + vertices + face + "xx")
                .find("2 bytes after the last element"),
            std::string::npos);
  std::string nan_vertices = vertices;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  nan_vertices.replace(4 * 8, 8, Bytes(nan));
  EXPECT_NE(ReadError(header + nan_vertices + face)
                .find("vertex 1: non-finite vertex coordinate"),
            std::string::npos);
  const std::string bad_face = Bytes(uint8_t{3}) + Bytes(int32_t{0}) +
                               Bytes(int32_t{1}) + Bytes(int32_t{2});
  EXPECT_NE(ReadError(header + vertices + bad_face)
                .find("face 0: vertex index 2 out of range (2 vertices)"),
            std::string::npos);
  // A corrupt count is reported, not allocated.
  std::string huge = header;
  huge.replace(huge.find("face 1"), 6, "face 999999999");
  EXPECT_NE(ReadError(huge + vertices + face).find("cannot fit"),
            std::string::npos);
}

TEST_F(MeshTest, WriteRefusesMeshesItCouldNotReadBack) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 3}};
  const std::filesystem::path path = dir_ / "out.ply";
  EXPECT_THROW(WritePly(mesh, path, "frame"), Error);
  mesh.triangles = {{0, 1, 2}};
  // A frame that would break the header, or none.
  EXPECT_THROW(WritePly(mesh, path, "two\nlines"), Error);
  EXPECT_THROW(WritePly(mesh, path, ""), Error);
  mesh.vertices[1].y() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(WritePly(mesh, path, "frame"), Error);
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST_F(MeshTest, ReadsObjWithPolygonsAndSlashedIndices) {
  const std::filesystem::path path =
      Write("quad.obj",
            "# a unit square and a triangle by negative indices\n"
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\n"
            "f 1//1 2//1 3//1 4//1\nv 0 0 1\nf -1 1 2\n");
  const TriangleMesh mesh = ReadMesh(path);
  ASSERT_EQ(mesh.vertices.size(), 5u);
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(mesh.triangles[0], Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(mesh.triangles[1], Eigen::Vector3i(0, 2, 3));
  EXPECT_EQ(mesh.triangles[2], Eigen::Vector3i(4, 0, 1));
  for (const auto& [name, text, words] :
       std::vector<std::array<std::string, 3>>{
           {"bad1.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n", "bad1.obj:3"},
           {"bad2.obj", "v 0 0\n", "bad2.obj:1"},
           {"bad3.obj", "v 0 0 0\n", "no faces"},
           {"bad4.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x 3\n", "bad face"}}) {
    try {
      ReadObj(Write(name, text));
      ADD_FAILURE() << name;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(words), std::string::npos)
          << error.what();
    }
  }
  EXPECT_THROW(ReadMesh(Write("mesh.stl", "solid")), Error);
}

}  // namespace
}  // namespace uw
