// Our reading and writing of COLMAP sparse models against stock colmap 3.8,
// on a model that stock colmap reconstructed from the rendered test scene
// (fixture colmap_scene, built by scripts/reconstruct_test_scene.sh).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include "colmap_plugins/scene/model_io.h"
#include "colmap_plugins/scene/model_stats.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/subprocess.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;

const fs::path kSceneDir = UW_SCENE_DIR;
const fs::path kSparseDir = kSceneDir / "sparse" / "0";
const fs::path kUwcolmap = fs::path(UW_BIN_DIR) / "uwcolmap";

std::vector<std::string> ModelFileNames(const std::string& extension) {
  return {"cameras" + extension, "images" + extension, "points3D" + extension};
}

// Splits a COLMAP text file into its header comment lines and its records
// keyed by id (the first field); an images.txt record is its two lines.
struct TextRecords {
  std::vector<std::string> header;
  std::map<std::string, std::string> records;
};

TextRecords SplitRecords(const std::string& text, bool two_lines_per_record) {
  TextRecords result;
  std::istringstream stream(text);
  std::string line;
  while (std::getline(stream, line)) {
    if (!line.empty() && line[0] == '#') {
      result.header.push_back(line);
      continue;
    }
    std::string record = line;
    if (two_lines_per_record) {
      std::string second;
      std::getline(stream, second);
      record += "\n" + second;
    }
    const std::string id = line.substr(0, line.find(' '));
    EXPECT_TRUE(result.records.emplace(id, record).second)
        << "duplicate " << id;
  }
  return result;
}

TEST(ColmapModel, SceneWasReconstructedByStockColmap) {
  const Reconstruction model = ReadModel(kSparseDir);
  // The fixture renders 12 images; all must register for the comparisons
  // below to cover a realistic model.
  EXPECT_EQ(model.Images().size(), 12u);
  EXPECT_GT(model.Points3D().size(), 1000u);
  EXPECT_EQ(model.Cameras()[0].model_id, CameraModelId::kSimpleRadial);
}

TEST(ColmapModel, BinaryModelIsWrittenBackByteIdentical) {
  const fs::path out = FreshTestDir("uw_colmap_model_test");
  WriteModel(ReadModel(kSparseDir), out, ModelFormat::kBinary);
  for (const std::string& name : ModelFileNames(".bin")) {
    const std::string original = ReadFileToString(kSparseDir / name);
    const std::string ours = ReadFileToString(out / name);
    EXPECT_EQ(original.size(), ours.size()) << name;
    EXPECT_TRUE(original == ours) << name << " differs";
  }
}

// Converts `model_dir` to text with stock colmap and with uwcolmap and
// compares the files header line for header line and record for record.
void ExpectTextEqualsColmapConverter(const fs::path& model_dir,
                                     const fs::path& dir) {
  const fs::path theirs = dir / "colmap_txt";
  const fs::path ours = dir / "uw_txt";
  fs::create_directories(theirs);
  const auto converted =
      RunProcess("colmap model_converter --input_path " + Quoted(model_dir) +
                     " --output_path " + Quoted(theirs) + " --output_type TXT",
                 true);
  ASSERT_EQ(converted.exit_code, 0) << converted.output;
  const auto cli =
      RunProcess(kUwcolmap.string() + " model_converter" + " --input_path " +
                     Quoted(model_dir) + " --output_path " + Quoted(ours) +
                     " --output_type TXT",
                 true);
  ASSERT_EQ(cli.exit_code, 0) << cli.output;
  for (const std::string& name : ModelFileNames(".txt")) {
    const bool two_lines = name == "images.txt";
    const TextRecords a =
        SplitRecords(ReadFileToString(theirs / name), two_lines);
    const TextRecords b =
        SplitRecords(ReadFileToString(ours / name), two_lines);
    EXPECT_EQ(a.header, b.header) << name;
    ASSERT_FALSE(a.records.empty()) << name;
    ASSERT_EQ(a.records.size(), b.records.size()) << name;
    size_t num_different = 0;
    for (const auto& [id, record] : a.records) {
      const auto it = b.records.find(id);
      ASSERT_NE(it, b.records.end()) << name << " lacks record " << id;
      if (it->second != record && num_different++ < 3) {
        ADD_FAILURE() << name << " record " << id << "\ncolmap: " << record
                      << "\nours:   " << it->second;
      }
    }
    EXPECT_EQ(num_different, 0u) << name << ": records that differ";
  }
}

TEST(ColmapModel, TextEqualsColmapModelConverterRecordForRecord) {
  ExpectTextEqualsColmapConverter(kSparseDir,
                                  FreshTestDir("uw_colmap_model_test"));
}

// COLMAP normalises quaternions when it reads a model and again when it
// writes text; a model whose quaternions are not unit (e.g. written by
// another tool) must still come out as colmap writes it.
TEST(ColmapModel, TextOfNonUnitQuaternionsEqualsColmapModelConverter) {
  const fs::path dir = FreshTestDir("uw_colmap_model_test");
  Reconstruction model = ReadModel(kSparseDir);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> scale(0.9, 1.1);
  for (Image& image : model.Images()) {
    image.cam_from_world.rotation.coeffs() *= scale(rng);
  }
  WriteModel(model, dir / "scaled", ModelFormat::kBinary);
  ExpectTextEqualsColmapConverter(dir / "scaled", dir);
}

std::string ColmapAnalyzerOutput(const fs::path& model_dir) {
  const auto result =
      RunProcess("colmap model_analyzer --path " + Quoted(model_dir), false);
  EXPECT_EQ(result.exit_code, 0);
  return result.output;
}

TEST(ColmapModel, StockColmapReadsWhatWeWrite) {
  const Reconstruction original = ReadModel(kSparseDir);
  const std::string reference = ColmapAnalyzerOutput(kSparseDir);
  ASSERT_NE(reference.find("Registered images: 12"), std::string::npos)
      << reference;
  const fs::path dir = FreshTestDir("uw_colmap_model_test");
  for (const ModelFormat format : {ModelFormat::kBinary, ModelFormat::kText}) {
    const fs::path ours =
        dir / (format == ModelFormat::kBinary ? "bin" : "txt");
    WriteModel(original, ours, format);
    EXPECT_EQ(ColmapAnalyzerOutput(ours), reference);
  }
  // colmap converts our text back to binary: same model (quaternions up to
  // COLMAP's re-normalisation, everything else to the bit).
  const fs::path back = dir / "back";
  fs::create_directories(back);
  const auto converted =
      RunProcess("colmap model_converter --input_path " + Quoted(dir / "txt") +
                     " --output_path " + Quoted(back) + " --output_type BIN",
                 true);
  ASSERT_EQ(converted.exit_code, 0) << converted.output;
  const Reconstruction round = ReadModel(back);
  ASSERT_EQ(round.Images().size(), original.Images().size());
  for (const Image& image : original.Images()) {
    const Image* other = round.FindImage(image.image_id);
    ASSERT_NE(other, nullptr);
    EXPECT_LT(other->cam_from_world.rotation.angularDistance(
                  image.cam_from_world.rotation),
              1e-14);
    EXPECT_EQ(other->cam_from_world.translation,
              image.cam_from_world.translation);
    EXPECT_EQ(other->name, image.name);
    ASSERT_EQ(other->points2D.size(), image.points2D.size());
    for (size_t i = 0; i < image.points2D.size(); ++i) {
      EXPECT_EQ(other->points2D[i].xy, image.points2D[i].xy);
      EXPECT_EQ(other->points2D[i].point3D_id, image.points2D[i].point3D_id);
    }
  }
  for (const Point3D& point3D : original.Points3D()) {
    const Point3D* other = round.FindPoint3D(point3D.point3D_id);
    ASSERT_NE(other, nullptr);
    EXPECT_EQ(other->xyz, point3D.xyz);
    EXPECT_EQ(other->error, point3D.error);
    EXPECT_EQ(other->track.size(), point3D.track.size());
  }
}

// Reads "Name: value" lines of colmap model_analyzer's output.
std::map<std::string, double> ParseAnalyzer(const std::string& output) {
  std::map<std::string, double> values;
  std::istringstream stream(output);
  std::string line;
  while (std::getline(stream, line)) {
    const size_t colon = line.find(": ");
    if (colon == std::string::npos) continue;
    values[line.substr(0, colon)] = std::stod(line.substr(colon + 2));
  }
  return values;
}

TEST(ColmapModel, StatisticsEqualColmapModelAnalyzer) {
  const auto colmap = ParseAnalyzer(ColmapAnalyzerOutput(kSparseDir));
  ASSERT_EQ(colmap.size(), 8u);
  const Reconstruction model = ReadModel(kSparseDir);
  const ModelStats stats = ComputeModelStats(model);
  EXPECT_EQ(stats.num_cameras, colmap.at("Cameras"));
  EXPECT_EQ(stats.num_images, colmap.at("Images"));
  EXPECT_EQ(stats.num_reg_images, colmap.at("Registered images"));
  EXPECT_EQ(stats.num_points3D, colmap.at("Points"));
  EXPECT_EQ(stats.num_observations, colmap.at("Observations"));
  // colmap prints "%f": 6 decimals, so allow half a unit of the last one
  // on top of 1e-6 relative.
  const auto near = [](double ours, double printed) {
    return std::abs(ours - printed) <= 5e-7 + 1e-6 * std::abs(printed);
  };
  EXPECT_PRED2(near, stats.mean_track_length, colmap.at("Mean track length"));
  EXPECT_PRED2(near, stats.mean_observations_per_image,
               colmap.at("Mean observations per image"));
  EXPECT_PRED2(near, stats.mean_reprojection_error,
               colmap.at("Mean reprojection error"));
  // Recomputed from poses, cameras and points with our camera models: the
  // same errors colmap stored after its last bundle adjustment.
  const ReprojectionErrors errors = RecomputeReprojectionErrors(model);
  EXPECT_PRED2(near, errors.mean_point_error,
               colmap.at("Mean reprojection error"));
  EXPECT_EQ(errors.num_behind_camera, 0u);
  std::printf(
      "[ figures ] points %zu, observations %zu, mean error colmap "
      "%.6f px, ours stored %.9f px, recomputed %.9f px, max "
      "|recomputed - stored| %.3g px\n",
      stats.num_points3D, stats.num_observations,
      colmap.at("Mean reprojection error"), stats.mean_reprojection_error,
      errors.mean_point_error, errors.max_stored_error_difference);
}

TEST(ColmapModel, UwcolmapModelAnalyzerPrintsColmapsLines) {
  const std::string reference = ColmapAnalyzerOutput(kSparseDir);
  const auto ours = RunProcess(
      kUwcolmap.string() + " model_analyzer --path " + Quoted(kSparseDir),
      false);
  ASSERT_EQ(ours.exit_code, 0);
  EXPECT_EQ(ours.output.substr(0, reference.size()), reference);
  EXPECT_NE(ours.output.find("Recomputed mean reprojection error"),
            std::string::npos);
}

// Every camera model against COLMAP's own implementation: observations are
// our projections plus known offsets; `colmap point_filtering` with a
// threshold that filters nothing recomputes each point's mean reprojection
// error with COLMAP's camera models and stores it. Both must agree.
struct ModelCase {
  CameraModelId id;
  std::vector<double> params;
};

std::vector<ModelCase> CameraModelCases() {
  return {
      {CameraModelId::kSimplePinhole, {500, 320, 240}},
      {CameraModelId::kPinhole, {500, 510, 321, 239}},
      {CameraModelId::kSimpleRadial, {500, 320, 240, 0.05}},
      {CameraModelId::kRadial, {500, 320, 240, 0.05, -0.01}},
      {CameraModelId::kOpenCV, {500, 510, 320, 240, 0.05, -0.01, 1e-3, -2e-3}},
      {CameraModelId::kOpenCVFisheye,
       {300, 305, 320, 240, 0.05, -0.01, 2e-3, -1e-3}},
      {CameraModelId::kFullOpenCV,
       {500, 510, 320, 240, 0.05, -0.01, 1e-3, -2e-3, 1e-3, 0.01, -5e-3, 1e-3}},
      {CameraModelId::kFOV, {500, 510, 320, 240, 0.9}},
      {CameraModelId::kSimpleRadialFisheye, {300, 320, 240, 0.05}},
      {CameraModelId::kRadialFisheye, {300, 320, 240, 0.05, -0.01}},
      {CameraModelId::kThinPrismFisheye,
       {300, 305, 320, 240, 0.05, -0.01, 1e-3, -2e-3, 1e-3, -5e-4, 1e-3,
        -1e-3}},
  };
}

TEST(ColmapModel, EveryCameraModelProjectsLikeColmap) {
  const fs::path dir = FreshTestDir("uw_colmap_model_test");
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Reconstruction model;
  image_t next_image_id = 1;
  point3D_t next_point3D_id = 1;
  const auto cases = CameraModelCases();
  for (size_t c = 0; c < cases.size(); ++c) {
    const camera_t camera_id = static_cast<camera_t>(c + 1);
    model.AddCamera({camera_id, cases[c].id, 640, 480, cases[c].params});
    // Three views of a cloud of points about 5 m in front, seen up to about
    // 35 degrees off-axis.
    std::vector<image_t> image_ids;
    for (int v = 0; v < 3; ++v) {
      Image image;
      image.image_id = next_image_id++;
      image.camera_id = camera_id;
      image.name = CameraModelIdToName(cases[c].id) + "_" + std::to_string(v);
      image.cam_from_world.rotation =
          Eigen::AngleAxisd(0.05 * uniform(rng), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(0.05 * uniform(rng), Eigen::Vector3d::UnitX());
      image.cam_from_world.translation = Eigen::Vector3d(0.5 * (v - 1), 0, 0);
      image_ids.push_back(image.image_id);
      model.AddImage(image);
    }
    for (int p = 0; p < 40; ++p) {
      Point3D point3D;
      point3D.point3D_id = next_point3D_id++;
      const double depth = 4.0 + 2.0 * std::abs(uniform(rng));
      point3D.xyz = Eigen::Vector3d(0.7 * depth * uniform(rng),
                                    0.5 * depth * uniform(rng), depth);
      for (const image_t image_id : image_ids) {
        Image& image = model.Images()[image_id - 1];
        const Camera& camera = *model.FindCamera(camera_id);
        const double angle = M_PI * uniform(rng);
        const double length = 2.0 * std::abs(uniform(rng));
        Point2D point2D;
        point2D.xy = camera.ImgFromCam(image.cam_from_world * point3D.xyz) +
                     length * Eigen::Vector2d(std::cos(angle), std::sin(angle));
        point2D.point3D_id = point3D.point3D_id;
        point3D.track.push_back(
            {image_id, static_cast<point2D_t>(image.points2D.size())});
        image.points2D.push_back(point2D);
      }
      model.AddPoint3D(point3D);
    }
  }
  WriteModel(model, dir / "input", ModelFormat::kBinary);
  fs::create_directories(dir / "filtered");
  const auto filtered = RunProcess(
      "colmap point_filtering --input_path " + Quoted(dir / "input") +
          " --output_path " + Quoted(dir / "filtered") +
          " --max_reproj_error 1e9 --min_tri_angle 0 --min_track_len 2",
      true);
  ASSERT_EQ(filtered.exit_code, 0) << filtered.output;
  const Reconstruction theirs = ReadModel(dir / "filtered");
  ASSERT_EQ(theirs.Points3D().size(), model.Points3D().size());
  std::vector<double> max_difference(cases.size(), 0.0);
  for (const Point3D& point3D : theirs.Points3D()) {
    const Point3D& ours = *model.FindPoint3D(point3D.point3D_id);
    double error_sum = 0.0;
    for (const TrackElement& element : ours.track) {
      const Image& image = *model.FindImage(element.image_id);
      const Camera& camera = *model.FindCamera(image.camera_id);
      error_sum += (camera.ImgFromCam(image.cam_from_world * ours.xyz) -
                    image.points2D[element.point2D_idx].xy)
                       .norm();
    }
    const double our_error = error_sum / ours.track.size();
    const size_t c = model.FindImage(ours.track[0].image_id)->camera_id - 1;
    max_difference[c] =
        std::max(max_difference[c], std::abs(our_error - point3D.error));
  }
  for (size_t c = 0; c < cases.size(); ++c) {
    EXPECT_LT(max_difference[c], 1e-9) << CameraModelIdToName(cases[c].id);
    std::printf(
        "[ figures ] %-22s max |ours - colmap| mean point error %.3g px\n",
        CameraModelIdToName(cases[c].id).c_str(), max_difference[c]);
  }
}

// Bad input through the CLI: a clear error naming file and position, a
// non-zero exit, and nothing written.
void ExpectCliRejects(const fs::path& model_dir, const std::string& expected) {
  const fs::path out = model_dir.parent_path() / "out";
  const auto result =
      RunProcess(kUwcolmap.string() + " model_converter --input_path " +
                     Quoted(model_dir) + " --output_path " + Quoted(out) +
                     " --output_type BIN",
                 true);
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find(expected), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(out)) << "output written despite the error";
}

TEST(ColmapModel, CliRefusesToConvertAModelInPlace) {
  const fs::path dir = FreshTestDir("uw_colmap_model_test") / "model";
  WriteModel(ReadModel(kSparseDir), dir, ModelFormat::kText);
  const std::string before = ReadFileToString(dir / "images.txt");
  const auto result = RunProcess(
      kUwcolmap.string() + " model_converter --input_path " + Quoted(dir) +
          " --output_path " + Quoted(dir / ".") + " --output_type TXT",
      true);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("is the input folder"), std::string::npos)
      << result.output;
  EXPECT_TRUE(ReadFileToString(dir / "images.txt") == before);
}

TEST(ColmapModel, CliRejectsTruncatedBinaryWithFileAndOffset) {
  const fs::path dir = FreshTestDir("uw_colmap_model_test") / "model";
  fs::create_directories(dir);
  for (const std::string& name : ModelFileNames(".bin")) {
    fs::copy_file(kSparseDir / name, dir / name);
  }
  const auto size = fs::file_size(dir / "images.bin");
  fs::resize_file(dir / "images.bin", size - 5);
  ExpectCliRejects(dir, (dir / "images.bin").string() + ": byte ");
}

TEST(ColmapModel, CliRejectsMalformedTextWithFileAndLine) {
  const fs::path base = FreshTestDir("uw_colmap_model_test");
  const Reconstruction model = ReadModel(kSparseDir);
  struct Case {
    const char* file;
    std::function<std::string(std::string)> edit;
    std::string expected;
  };
  const std::vector<Case> cases = {
      // One parameter too few for SIMPLE_RADIAL.
      {"cameras.txt",
       [](std::string text) { return text.substr(0, text.rfind(' ')) + "\n"; },
       "cameras.txt:4: camera 1: model SIMPLE_RADIAL expects 4 parameters"},
      // A letter inside the first image's rotation.
      {"images.txt",
       [](std::string text) {
         const size_t line5 = text.find('\n', text.find("# Number")) + 1;
         const size_t field = text.find(' ', text.find(' ', line5) + 1);
         text[field + 1] = 'x';
         return text;
       },
       "images.txt:5: expected pose"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const fs::path dir = base / std::to_string(i) / "model";
    WriteModel(model, dir, ModelFormat::kText);
    const fs::path file = dir / cases[i].file;
    const std::string edited = cases[i].edit(ReadFileToString(file));
    std::ofstream(file, std::ios::trunc) << edited;
    ExpectCliRejects(dir, cases[i].expected);
  }
}

}  // namespace
}  // namespace uw
