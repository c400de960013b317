#include "common/util/json_fields.h"

#include <algorithm>

namespace uw {

nlohmann::json ToJson(const Eigen::Vector3d& value) {
  return nlohmann::json::array({value.x(), value.y(), value.z()});
}

nlohmann::json ToJson(const Eigen::Matrix3d& value) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) {
    rows.push_back(ToJson(Eigen::Vector3d(value.row(r).transpose())));
  }
  return rows;
}

nlohmann::json ToJson(const std::vector<Eigen::Vector3d>& values) {
  nlohmann::json array = nlohmann::json::array();
  for (const Eigen::Vector3d& value : values) array.push_back(ToJson(value));
  return array;
}

nlohmann::json ParseJsonText(const std::string& text,
                             const std::string& where) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& error) {
    throw ErrorAt(where, ": ", error.what());
  }
}

JsonFields::JsonFields(const nlohmann::json& json, std::string what)
    : json_(json), what_(std::move(what)) {
  if (!json_.is_object()) {
    throw ErrorAt(what_, ": expected a JSON object, got ", json_.dump());
  }
}

bool JsonFields::Read(const std::string& key, double* value) {
  const nlohmann::json* item = Find(key);
  if (item == nullptr) return false;
  if (!item->is_number()) Fail(key, "a number", *item);
  *value = item->get<double>();
  return true;
}

bool JsonFields::Read(const std::string& key, bool* value) {
  const nlohmann::json* item = Find(key);
  if (item == nullptr) return false;
  if (!item->is_boolean()) Fail(key, "true or false", *item);
  *value = item->get<bool>();
  return true;
}

bool JsonFields::Read(const std::string& key, std::string* value) {
  const nlohmann::json* item = Find(key);
  if (item == nullptr) return false;
  if (!item->is_string()) Fail(key, "a string", *item);
  *value = item->get<std::string>();
  return true;
}

bool JsonFields::Read(const std::string& key, std::vector<double>* value) {
  const nlohmann::json* item = Find(key);
  if (item == nullptr) return false;
  if (!item->is_array() ||
      !std::all_of(item->begin(), item->end(),
                   [](const nlohmann::json& x) { return x.is_number(); })) {
    Fail(key, "an array of numbers", *item);
  }
  *value = item->get<std::vector<double>>();
  return true;
}

bool JsonFields::Read(const std::string& key, std::array<double, 3>* value) {
  const nlohmann::json* item = Find(key);
  if (item == nullptr) return false;
  const Eigen::Vector3d read = Vector3(*item, key);
  *value = {read.x(), read.y(), read.z()};
  return true;
}

bool JsonFields::Read(const std::string& key, Eigen::Vector3d* value) {
  const nlohmann::json* item = Find(key);
  if (item == nullptr) return false;
  *value = Vector3(*item, key);
  return true;
}

bool JsonFields::Read(const std::string& key,
                      std::optional<Eigen::Vector3d>* value) {
  const nlohmann::json* item = Find(key);
  if (item == nullptr) return false;
  if (item->is_null()) {
    value->reset();
  } else {
    *value = Vector3(*item, key);
  }
  return true;
}

bool JsonFields::Read(const std::string& key,
                      std::vector<Eigen::Vector3d>* value) {
  const nlohmann::json* item = Find(key);
  if (item == nullptr) return false;
  if (!item->is_array()) Fail(key, "an array of [x, y, z]", *item);
  std::vector<Eigen::Vector3d> read;
  for (const nlohmann::json& element : *item) {
    read.push_back(Vector3(element, key));
  }
  *value = std::move(read);
  return true;
}

bool JsonFields::Read(const std::string& key, Eigen::Matrix3d* value) {
  const nlohmann::json* item = Find(key);
  if (item == nullptr) return false;
  if (!item->is_array() || item->size() != 3) {
    Fail(key, "an array of 3 rows of 3 numbers", *item);
  }
  for (int r = 0; r < 3; ++r) value->row(r) = Vector3((*item)[r], key);
  return true;
}

void JsonFields::RequireFormat(const std::string& format, int version) {
  RequireFormat(format, version, version);
}

int JsonFields::RequireFormat(const std::string& format, int oldest_version,
                              int newest_version) {
  std::string read_format;
  int read_version = 0;
  Require("format", &read_format);
  Require("version", &read_version);
  if (read_format != format || read_version < oldest_version ||
      read_version > newest_version) {
    const std::string versions = oldest_version == newest_version
                                     ? std::to_string(newest_version)
                                     : std::to_string(oldest_version) + " to " +
                                           std::to_string(newest_version);
    throw ErrorAt(what_, ": expected format \"", format, "\" version ",
                  versions, ", got \"", read_format, "\" version ",
                  read_version);
  }
  return read_version;
}

void JsonFields::RejectUnknown() const {
  for (const auto& item : json_.items()) {
    if (std::find(known_.begin(), known_.end(), item.key()) == known_.end()) {
      std::string valid;
      for (const std::string& key : known_) {
        valid += (valid.empty() ? "" : ", ") + key;
      }
      throw ErrorAt(what_, ": unknown key \"", item.key(), "\" (valid: ", valid,
                    ")");
    }
  }
}

const nlohmann::json* JsonFields::Find(const std::string& key) {
  if (std::find(known_.begin(), known_.end(), key) == known_.end()) {
    known_.push_back(key);
  }
  const auto it = json_.find(key);
  return it == json_.end() ? nullptr : &*it;
}

void JsonFields::Fail(const std::string& key, const std::string& expected,
                      const nlohmann::json& value) const {
  throw ErrorAt(what_, ".", key, ": expected ", expected, ", got ",
                value.dump());
}

Eigen::Vector3d JsonFields::Vector3(const nlohmann::json& value,
                                    const std::string& key) const {
  if (!value.is_array() || value.size() != 3 ||
      !std::all_of(value.begin(), value.end(),
                   [](const nlohmann::json& x) { return x.is_number(); })) {
    Fail(key, "an array of 3 numbers", value);
  }
  return {value[0].get<double>(), value[1].get<double>(),
          value[2].get<double>()};
}

}  // namespace uw
