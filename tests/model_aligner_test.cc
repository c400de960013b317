// uwcolmap model_aligner against stock `colmap model_aligner` (3.8) on the
// model stock colmap reconstructed from the rendered test scene (fixture
// colmap_scene), with the scene's true camera centres as references.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <regex>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "colmap_plugins/nav/geodesy.h"
#include "colmap_plugins/scene/model_io.h"
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
const fs::path kRefImages = kSceneDir / "scene" / "truth" / "ref_images.txt";
const fs::path kUwcolmap = fs::path(UW_BIN_DIR) / "uwcolmap";

ProcessResult Uwcolmap(const std::string& flags) {
  return RunProcess(kUwcolmap.string() + " model_aligner " + flags, true);
}

std::string InOut(const fs::path& input, const fs::path& output) {
  return "--input_path " + Quoted(input) + " --output_path " + Quoted(output);
}

std::map<std::string, const Image*> ByName(const Reconstruction& model) {
  std::map<std::string, const Image*> images;
  for (const Image& image : model.Images()) images[image.name] = &image;
  return images;
}

TEST(ModelAligner, AgreesWithStockColmap) {
  const fs::path dir = FreshTestDir("uw_model_aligner_test");
  // colmap 3.8 aborts when the output folder does not exist.
  fs::create_directories(dir / "colmap");
  const auto colmap = RunProcess(
      "colmap model_aligner " + InOut(kSparseDir, dir / "colmap") +
          " --ref_images_path " + Quoted(kRefImages) +
          " --ref_is_gps 0 --alignment_type custom --robust_alignment 0",
      true);
  ASSERT_EQ(colmap.exit_code, 0) << colmap.output;
  const auto ours = Uwcolmap(InOut(kSparseDir, dir / "ours") +
                             " --ref_images_path " + Quoted(kRefImages) +
                             " --ref_is_gps 0 --alignment_type custom "
                             "--robust_alignment 0 --transform_path " +
                             Quoted(dir / "sim3.json"));
  ASSERT_EQ(ours.exit_code, 0) << ours.output;

  const Reconstruction theirs_model = ReadModel(dir / "colmap");
  const Reconstruction our_model = ReadModel(dir / "ours");
  ASSERT_EQ(our_model.Images().size(), theirs_model.Images().size());
  const auto theirs = ByName(theirs_model);
  double max_centre = 0.0;
  double max_rotation = 0.0;
  for (const Image& image : our_model.Images()) {
    const Image& other = *theirs.at(image.name);
    max_centre =
        std::max(max_centre,
                 (image.ProjectionCenter() - other.ProjectionCenter()).norm());
    max_rotation =
        std::max(max_rotation, image.cam_from_world.rotation.angularDistance(
                                   other.cam_from_world.rotation.normalized()));
  }
  double max_point = 0.0;
  for (const Point3D& point : our_model.Points3D()) {
    max_point = std::max(
        max_point,
        (point.xyz - theirs_model.FindPoint3D(point.point3D_id)->xyz).norm());
  }
  // colmap prints the mean and median distance of the aligned centres to
  // their references.
  std::smatch match;
  ASSERT_TRUE(std::regex_search(
      colmap.output, match,
      std::regex(
          R"(Alignment error: ([0-9.e+-]+) \(mean\), ([0-9.e+-]+) \(median\))")))
      << colmap.output;
  const nlohmann::json sim3 =
      nlohmann::json::parse(ReadFileToString(dir / "sim3.json"));
  std::vector<double> errors;
  for (const auto& image : sim3.at("images")) {
    errors.push_back(image.at("residual_norm_m").get<double>());
  }
  double mean = 0.0;
  for (const double error : errors) mean += error / errors.size();
  std::sort(errors.begin(), errors.end());
  std::printf(
      "[ figures ] model_aligner vs colmap model_aligner on %zu images: max "
      "|centre difference| %.3g m, max rotation difference %.3g rad, max "
      "|point difference| %.3g m; residual mean %.6f m (colmap %s), "
      "RMS %.6f m\n",
      errors.size(), max_centre, max_rotation, max_point, mean,
      match[1].str().c_str(), sim3.at("rms_m").get<double>());
  EXPECT_LT(max_centre, 1e-6);
  EXPECT_LT(max_rotation, 1e-8);
  EXPECT_LT(max_point, 1e-6);
  EXPECT_NEAR(mean, std::stod(match[1].str()), 1e-6);
  EXPECT_EQ(sim3.at("num_images").get<int>(), 12);

  // Stock colmap reads our output.
  const auto analyzer =
      RunProcess("colmap model_analyzer --path " + Quoted(dir / "ours"), true);
  EXPECT_EQ(analyzer.exit_code, 0) << analyzer.output;
  EXPECT_NE(analyzer.output.find("Registered images: 12"), std::string::npos)
      << analyzer.output;
}

TEST(ModelAligner, WritesTextForTextAndKeepsRelativeGeometry) {
  const fs::path dir = FreshTestDir("uw_model_aligner_test");
  ASSERT_EQ(
      RunProcess(kUwcolmap.string() + " model_converter " +
                     InOut(kSparseDir, dir / "txt") + " --output_type TXT",
                 true)
          .exit_code,
      0);
  const auto result = Uwcolmap(InOut(dir / "txt", dir / "aligned") +
                               " --ref_images_path " + Quoted(kRefImages));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(fs::exists(dir / "aligned" / "images.txt"));
  EXPECT_FALSE(fs::exists(dir / "aligned" / "images.bin"));
  // The stored reprojection errors still hold: poses and points moved
  // together.
  const auto analyzer = RunProcess(
      kUwcolmap.string() + " model_analyzer --path " + Quoted(dir / "aligned"),
      true);
  std::smatch match;
  ASSERT_TRUE(std::regex_search(
      analyzer.output, match,
      std::regex(R"(max \|recomputed - stored\| per point ([0-9.e+-]+)px)")))
      << analyzer.output;
  EXPECT_LT(std::stod(match[1].str()), 1e-6) << analyzer.output;
}

// One reference 1 m off: the robust alignment lists it and keeps the
// transform of the clean references.
TEST(ModelAligner, RobustAlignmentSetsAWrongReferenceAside) {
  const fs::path dir = FreshTestDir("uw_model_aligner_test");
  std::ifstream in(kRefImages);
  std::ofstream out(dir / "ref.txt");
  std::string name;
  double x, y, z;
  while (in >> name >> x >> y >> z) {
    out << name << " " << x << " " << y << " "
        << (name == "005.png" ? z + 1.0 : z) << "\n";
  }
  out.close();
  const auto clean = Uwcolmap(
      InOut(kSparseDir, dir / "clean") + " --ref_images_path " +
      Quoted(kRefImages) + " --transform_path " + Quoted(dir / "clean.json"));
  ASSERT_EQ(clean.exit_code, 0) << clean.output;
  const auto result =
      Uwcolmap(InOut(kSparseDir, dir / "aligned") + " --ref_images_path " +
               Quoted(dir / "ref.txt") + " --transform_path " +
               Quoted(dir / "sim3.json"));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("Outlier: 005.png"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("Inliers: 11 of 12"), std::string::npos)
      << result.output;
  const auto matrix = [&](const std::string& file) {
    return nlohmann::json::parse(ReadFileToString(dir / file))
        .at("reference_from_model")
        .at("matrix");
  };
  double max_difference = 0.0;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      max_difference = std::max(
          max_difference, std::abs(matrix("sim3.json")[r][c].get<double>() -
                                   matrix("clean.json")[r][c].get<double>()));
    }
  }
  EXPECT_LT(max_difference, 2e-3);
}

// The references rewritten by `rewrite` (name, x, y, z of each line) into
// `path`.
void RewriteReferences(
    const fs::path& path,
    const std::function<void(std::string*, Eigen::Vector3d*)>& rewrite) {
  std::ifstream in(kRefImages);
  std::vector<std::pair<std::string, Eigen::Vector3d>> references;
  std::string name;
  double x, y, z;
  while (in >> name >> x >> y >> z) references.push_back({name, {x, y, z}});
  std::ofstream out(path);
  out.precision(17);
  for (auto& [name, position] : references) {
    rewrite(&name, &position);
    out << name << " " << position.x() << " " << position.y() << " "
        << position.z() << "\n";
  }
}

void ExpectFailsWritingNothing(const std::string& flags, const fs::path& output,
                               const std::string& message) {
  const auto result = Uwcolmap(flags);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find(message), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(output)) << output;
}

TEST(ModelAligner, BadReferencesGiveClearErrorsAndWriteNothing) {
  const fs::path dir = FreshTestDir("uw_model_aligner_test");
  const fs::path output = dir / "aligned";
  const std::string json = " --transform_path " + Quoted(dir / "sim3.json");
  {
    std::ofstream out(dir / "prefixed.txt");
    std::ifstream in(kRefImages);
    std::string name;
    double x, y, z;
    while (in >> name >> x >> y >> z) {
      out << "images/" << name << " " << x << " " << y << " " << z << "\n";
    }
  }
  ExpectFailsWritingNothing(
      InOut(kSparseDir, output) + " --ref_images_path " +
          Quoted(dir / "prefixed.txt") + json,
      output,
      "0 of its 12 positions name an image of the model (12 images); at "
      "least 3 are needed (e.g. reference 'images/000.png', model "
      "'000.png')");
  {
    std::ofstream out(dir / "line.txt");
    for (int k = 0; k < 12; ++k) {
      char name[16];
      std::snprintf(name, sizeof(name), "%03d.png", k);
      out << name << " " << k << " " << 2 * k << " 1\n";
    }
  }
  ExpectFailsWritingNothing(InOut(kSparseDir, output) + " --ref_images_path " +
                                Quoted(dir / "line.txt") + json,
                            output, "the 12 target points are collinear");
  ExpectFailsWritingNothing(InOut(kSparseDir, output) + " --ref_images_path " +
                                Quoted(kRefImages) + " --nav nav.csv" + json,
                            output,
                            "give exactly one of --ref_images_path, "
                            "--database_path and --nav (got 2)");
  ExpectFailsWritingNothing(InOut(kSparseDir, output) + " --ref_images_path " +
                                Quoted(kRefImages) + " --ref_is_gps 1" + json,
                            output,
                            "--ref_is_gps 1 aligns into local east-north-up "
                            "metres: give --alignment_type enu");
  {
    std::ofstream out(dir / "broken.txt");
    out << "000.png 1 2 3\n001.png 1 2\n";
  }
  ExpectFailsWritingNothing(InOut(kSparseDir, output) + " --ref_images_path " +
                                Quoted(dir / "broken.txt") + json,
                            output,
                            "broken.txt:2: expected 'image_name x y z'");
  EXPECT_FALSE(fs::exists(dir / "sim3.json"));
  const auto same = Uwcolmap(InOut(kSparseDir, kSparseDir) +
                             " --ref_images_path " + Quoted(kRefImages));
  EXPECT_EQ(same.exit_code, 1);
  EXPECT_NE(same.output.find("is the input folder"), std::string::npos)
      << same.output;
}

// Issue 17: COLMAP's GPS references (--ref_is_gps 1, 'name lat lon alt')
// are aligned to in local east-north-up metres at --origin: the model lands
// where the metric references they were made from put it, to < 1 mm.
TEST(ModelAligner, GpsReferencesAlignInLocalEastNorthUp) {
  const fs::path dir = FreshTestDir("uw_model_aligner_gps");
  const LocalEnu local({-33.875, 151.25, 10.0});
  {
    std::ifstream in(kRefImages);
    std::ofstream out(dir / "gps.txt");
    std::string name;
    double x, y, z;
    while (in >> name >> x >> y >> z) {
      const Eigen::Vector3d geodetic = local.ToGeodetic({x, y, z});
      out << fmt::format("{} {:.12f} {:.12f} {:.6f}\n", name, geodetic.x(),
                         geodetic.y(), geodetic.z());
    }
  }
  const auto metric =
      Uwcolmap(InOut(kSparseDir, dir / "metric") + " --ref_images_path " +
               Quoted(kRefImages) + " --robust_alignment 0");
  ASSERT_EQ(metric.exit_code, 0) << metric.output;
  const std::string gps_flags = " --ref_images_path " +
                                Quoted(dir / "gps.txt") +
                                " --ref_is_gps 1 --robust_alignment 0";
  const auto gps = Uwcolmap(
      InOut(kSparseDir, dir / "gps") + gps_flags +
      " --alignment_type enu --origin -33.875,151.25,10 --transform_path " +
      Quoted(dir / "sim3.json"));
  ASSERT_EQ(gps.exit_code, 0) << gps.output;
  const Reconstruction metric_model = ReadModel(dir / "metric");
  const auto metric_images = ByName(metric_model);
  double max_centre = 0.0;
  const Reconstruction gps_model = ReadModel(dir / "gps");
  for (const Image& image : gps_model.Images()) {
    max_centre =
        std::max(max_centre, (image.ProjectionCenter() -
                              metric_images.at(image.name)->ProjectionCenter())
                                 .norm());
  }
  std::printf("[ gps ] largest camera-centre difference %.2e m\n", max_centre);
  EXPECT_LT(max_centre, 1e-3);
  const nlohmann::json sim3 =
      nlohmann::json::parse(ReadFileToString(dir / "sim3.json"));
  EXPECT_NE(sim3.at("world_frame")
                .get<std::string>()
                .find("local east-north-up (m) at -33.875"),
            std::string::npos)
      << sim3.at("world_frame");
  // Beside the model, in a form a GIS reads; none beside a metric one.
  const nlohmann::json frame =
      nlohmann::json::parse(ReadFileToString(dir / "gps" / "world_frame.json"));
  EXPECT_EQ(frame.at("format"), "uwmetric-world-frame");
  EXPECT_EQ(frame.at("origin").at("lat_deg"), -33.875);
  EXPECT_EQ(frame.at("origin").at("lon_deg"), 151.25);
  EXPECT_EQ(frame.at("origin").at("height_m"), 10.0);
  EXPECT_EQ(frame.at("origin").at("datum"), "WGS84");
  EXPECT_EQ(frame.at("axes"), nlohmann::json({"east", "north", "up"}));
  EXPECT_EQ(frame.at("origin_automatic"), false);
  EXPECT_FALSE(fs::exists(dir / "metric" / "world_frame.json"));
  // Aligned again into that folder, to metric references: the old frame
  // would lie, and goes.
  const auto again =
      Uwcolmap(InOut(kSparseDir, dir / "gps") + " --ref_images_path " +
               Quoted(kRefImages) + " --robust_alignment 0");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_FALSE(fs::exists(dir / "gps" / "world_frame.json"));

  // Without --origin: the first reference rounded, printed for reuse.
  const auto automatic = Uwcolmap(InOut(kSparseDir, dir / "automatic") +
                                  gps_flags + " --alignment_type enu");
  ASSERT_EQ(automatic.exit_code, 0) << automatic.output;
  EXPECT_NE(automatic.output.find("automatic, the first position rounded"),
            std::string::npos)
      << automatic.output;
  // colmap would align into ECEF without enu: the frame is asked for.
  const auto custom = Uwcolmap(InOut(kSparseDir, dir / "custom") + gps_flags);
  EXPECT_EQ(custom.exit_code, 1);
  EXPECT_NE(custom.output.find("give --alignment_type enu"), std::string::npos)
      << custom.output;
  EXPECT_FALSE(fs::exists(dir / "custom"));
}

// Issue 17: gross mistakes used to align with exit 0 and normal-looking
// output.
TEST(ModelAligner, GrossMistakesAreRefusedUnlessAccepted) {
  const fs::path dir = FreshTestDir("uw_model_aligner_test");
  const fs::path output = dir / "aligned";
  const std::string json = " --transform_path " + Quoted(dir / "sim3.json");
  // The references as longitude and latitude in degrees (at 43.1 N) with
  // the height in metres, read as metres: a fine fit at scale ~1e-5.
  RewriteReferences(dir / "degrees.txt", [](std::string*, Eigen::Vector3d* p) {
    constexpr double kMetresPerDegree = 111320.0;
    *p = Eigen::Vector3d(
        5.4 + p->x() / (kMetresPerDegree * std::cos(43.1 * M_PI / 180.0)),
        43.1 + p->y() / kMetresPerDegree, p->z());
  });
  const std::string degrees = " --ref_images_path " +
                              Quoted(dir / "degrees.txt") +
                              " --robust_alignment 0" + json;
  ExpectFailsWritingNothing(InOut(kSparseDir, output) + degrees, output,
                            "Are the positions latitude/longitude in degrees, "
                            "or another unit, read as metres?");
  EXPECT_FALSE(fs::exists(dir / "sim3.json"));
  const auto accepted = Uwcolmap(InOut(kSparseDir, dir / "accepted") + degrees +
                                 " --accept_implausible 1");
  ASSERT_EQ(accepted.exit_code, 0) << accepted.output;
  EXPECT_NE(accepted.output.find("(accepted: --accept_implausible 1)"),
            std::string::npos)
      << accepted.output;
  EXPECT_FALSE(
      nlohmann::json::parse(ReadFileToString(dir / "sim3.json"))["warnings"]
          .empty());

  // Each image paired with the position of another, image k with image
  // 5k + 3 (mod 12), as a log of another time puts unrelated positions
  // beside the images: the navigation does not follow the model.
  std::vector<std::string> names;
  RewriteReferences(
      dir / "unused.txt",
      [&](std::string* name, Eigen::Vector3d*) { names.push_back(*name); });
  size_t k = 0;
  RewriteReferences(dir / "shifted.txt",
                    [&](std::string* name, Eigen::Vector3d*) {
                      *name = names[(5 * k++ + 3) % names.size()];
                    });
  ExpectFailsWritingNothing(InOut(kSparseDir, output) + " --ref_images_path " +
                                Quoted(dir / "shifted.txt") +
                                " --robust_alignment 0" + json,
                            output,
                            "the navigation does not follow these images. Are "
                            "they paired with the navigation of another time "
                            "(a camera clock offset: --time_offset)");
  // The true references pass, and the printout says what was judged.
  const auto clean = Uwcolmap(InOut(kSparseDir, output) +
                              " --ref_images_path " + Quoted(kRefImages));
  ASSERT_EQ(clean.exit_code, 0) << clean.output;
  EXPECT_EQ(clean.output.find("WARNING"), std::string::npos) << clean.output;
  EXPECT_TRUE(std::regex_search(
      clean.output, std::regex("Plausibility: cameras [0-9.]+ m from what they "
                               "see \\(median of [0-9]+ depths\\); the "
                               "similarity explains (9[0-9.]+|100.0) %")))
      << clean.output;
}

}  // namespace
}  // namespace uw
