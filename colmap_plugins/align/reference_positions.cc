#include "colmap_plugins/align/reference_positions.h"

#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include <Eigen/Cholesky>

#include "colmap_plugins/nav/geographic_positions.h"
#include "common/util/error.h"
#include "common/util/file.h"

namespace uw {
namespace {

bool ParseFinite(const std::string& text, double* value) {
  size_t used = 0;
  try {
    *value = std::stod(text, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == text.size() && std::isfinite(*value);
}

bool PositiveDefinite(const Eigen::Matrix3d& covariance) {
  if (!covariance.allFinite() ||
      !covariance.isApprox(covariance.transpose(), 1e-9)) {
    return false;
  }
  const Eigen::LLT<Eigen::Matrix3d> llt(covariance);
  return llt.info() == Eigen::Success &&
         llt.matrixL().toDenseMatrix().diagonal().minCoeff() > 0.0;
}

}  // namespace

std::vector<ReferencePosition> ReadReferencePositions(
    const std::filesystem::path& path) {
  std::istringstream text(ReadFileToString(path));
  std::vector<ReferencePosition> references;
  std::set<std::string> names;
  std::string line;
  for (int line_number = 1; std::getline(text, line); ++line_number) {
    std::istringstream fields(line);
    std::vector<std::string> tokens;
    for (std::string token; fields >> token;) tokens.push_back(token);
    if (tokens.empty() || tokens[0][0] == '#') continue;
    if (tokens.size() != 4) {
      throw ErrorAt(path.string(), ":", line_number,
                    ": expected 'image_name x y z', got ", tokens.size(),
                    " fields");
    }
    ReferencePosition reference;
    reference.image_name = tokens[0];
    for (int axis = 0; axis < 3; ++axis) {
      if (!ParseFinite(tokens[1 + axis], &reference.position(axis))) {
        throw ErrorAt(path.string(), ":", line_number, ": '", tokens[1 + axis],
                      "' is not a finite number");
      }
    }
    if (!names.insert(reference.image_name).second) {
      throw ErrorAt(path.string(), ":", line_number, ": image '",
                    reference.image_name, "' is listed twice");
    }
    references.push_back(reference);
  }
  return references;
}

std::vector<ReferencePosition> ReferencePositionsFromDatabase(
    const Database& database, const std::optional<GeoOrigin>& origin,
    NavLogFrame* frame, std::vector<std::string>* warnings) {
  std::map<uint32_t, std::string> names;
  for (const DatabaseImage& image : database.ReadAllImages()) {
    names[image.image_id] = image.name;
  }
  std::vector<ReferencePosition> references;
  for (const PosePrior& prior :
       WithLocalPositions(database.ReadAllPosePriors(), origin,
                          database.Path().string(), frame, warnings)) {
    if (!prior.HasPosition()) continue;
    ReferencePosition reference;
    reference.image_name = names.at(prior.image_id);
    reference.position = prior.position;
    if (prior.HasPositionCovariance()) {
      reference.covariance = prior.position_covariance;
    }
    references.push_back(reference);
  }
  return references;
}

ReferenceMatch MatchReferencePositions(
    const Reconstruction& model,
    const std::vector<ReferencePosition>& references,
    const std::string& source) {
  std::map<std::string, const Image*> images;
  for (const Image& image : model.Images()) images[image.name] = &image;
  std::map<std::string, const ReferencePosition*> matched;
  ReferenceMatch match;
  for (const ReferencePosition& reference : references) {
    if (images.count(reference.image_name) > 0) {
      matched[reference.image_name] = &reference;
    } else {
      match.unknown_names.push_back(reference.image_name);
    }
  }
  if (matched.size() < 3) {
    throw ErrorAt(source, ": ", matched.size(), " of its ", references.size(),
                  " positions name an image of the model (", images.size(),
                  " images); at least 3 are needed",
                  references.empty() || images.empty()
                      ? std::string()
                      : " (e.g. reference '" + references.front().image_name +
                            "', model '" + images.begin()->first + "')");
  }
  bool all_covariances = true;
  for (const auto& [name, reference] : matched) {
    match.image_names.push_back(name);
    match.model_centres.push_back(images.at(name)->ProjectionCenter());
    match.reference_positions.push_back(reference->position);
    if (reference->covariance && PositiveDefinite(*reference->covariance)) {
      match.covariances.push_back(*reference->covariance);
    } else {
      all_covariances = false;
      ++match.num_without_covariance;
    }
  }
  if (!all_covariances) match.covariances.clear();
  return match;
}

}  // namespace uw
