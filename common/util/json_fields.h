// Reading and writing options structs as JSON (uwsim's sim.json, lasers.json
// and
// --config): every key read is known, anything else is an error naming it.
#pragma once

#include <algorithm>
#include <set>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "common/util/error.h"

namespace uw {

inline nlohmann::json ToJson(const Eigen::Vector3d& value) {
  return nlohmann::json::array({value.x(), value.y(), value.z()});
}

// A 3x3 matrix as an array of its rows.
inline nlohmann::json ToJson(const Eigen::Matrix3d& value) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) {
    rows.push_back(ToJson(Eigen::Vector3d(value.row(r).transpose())));
  }
  return rows;
}

// Parses a file's text; a syntax error or a number out of range (1e999)
// names `where` and the position.
inline nlohmann::json ParseJsonText(const std::string& text,
                                    const std::string& where) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& error) {
    throw ErrorAt(where, ": ", error.what());
  }
}

// Reads the keys of one options object and rejects the rest, naming them.
class JsonFields {
 public:
  JsonFields(const nlohmann::json& json, std::string what)
      : json_(json), what_(std::move(what)) {
    if (!json_.is_object()) {
      throw ErrorAt(what_, ": expected a JSON object, got ", json_.dump());
    }
  }

  template <typename T>
  void Read(const std::string& key, T* value) {
    known_.insert(key);
    const auto it = json_.find(key);
    if (it == json_.end()) return;
    try {
      it->get_to(*value);
    } catch (const nlohmann::json::exception& error) {
      throw ErrorAt(what_, ".", key, ": ", error.what());
    }
  }

  void Read(const std::string& key, Eigen::Vector3d* value) {
    known_.insert(key);
    const auto it = json_.find(key);
    if (it == json_.end()) return;
    *value = Vector3(*it, key);
  }

  void Read(const std::string& key, Eigen::Matrix3d* value) {
    known_.insert(key);
    const auto it = json_.find(key);
    if (it == json_.end()) return;
    if (!it->is_array() || it->size() != 3) {
      throw ErrorAt(what_, ".", key,
                    ": expected an array of 3 rows of 3 numbers, got ",
                    it->dump());
    }
    for (int r = 0; r < 3; ++r) value->row(r) = Vector3((*it)[r], key);
  }

  // Like Read, for a key that must be present.
  template <typename T>
  void Require(const std::string& key, T* value) {
    if (!json_.contains(key)) {
      throw ErrorAt(what_, ": missing key \"", key, "\"");
    }
    Read(key, value);
  }

  // A uwmetric file's "format" and "version": both required and ours.
  void RequireFormat(const std::string& format, int version) {
    std::string read_format;
    int read_version = 0;
    Require("format", &read_format);
    Require("version", &read_version);
    if (read_format != format || read_version != version) {
      throw ErrorAt(what_, ": expected format \"", format, "\" version ",
                    version, ", got \"", read_format, "\" version ",
                    read_version);
    }
  }

  void RejectUnknown() const {
    for (const auto& item : json_.items()) {
      if (known_.count(item.key()) == 0) {
        throw ErrorAt(what_, ": unknown key \"", item.key(), "\"");
      }
    }
  }

 private:
  Eigen::Vector3d Vector3(const nlohmann::json& json,
                          const std::string& key) const {
    if (!json.is_array() || json.size() != 3 ||
        !std::all_of(json.begin(), json.end(),
                     [](const nlohmann::json& x) { return x.is_number(); })) {
      throw ErrorAt(what_, ".", key, ": expected an array of 3 numbers, got ",
                    json.dump());
    }
    return {json[0].get<double>(), json[1].get<double>(),
            json[2].get<double>()};
  }

  const nlohmann::json& json_;
  std::string what_;
  std::set<std::string> known_;
};

}  // namespace uw
