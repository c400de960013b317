// Reading and writing options structs as JSON (uwsim's sim.json and
// --config): every key read is known, anything else is an error naming it.
#pragma once

#include <algorithm>
#include <set>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "colmap_plugins/util/error.h"

namespace uw::sim {

inline nlohmann::json ToJson(const Eigen::Vector3d& value) {
  return nlohmann::json::array({value.x(), value.y(), value.z()});
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
    if (!it->is_array() || it->size() != 3 ||
        !std::all_of(it->begin(), it->end(),
                     [](const nlohmann::json& x) { return x.is_number(); })) {
      throw ErrorAt(what_, ".", key, ": expected an array of 3 numbers, got ",
                    it->dump());
    }
    *value = {(*it)[0].get<double>(), (*it)[1].get<double>(),
              (*it)[2].get<double>()};
  }

  void RejectUnknown() const {
    for (const auto& item : json_.items()) {
      if (known_.count(item.key()) == 0) {
        throw ErrorAt(what_, ": unknown key \"", item.key(), "\"");
      }
    }
  }

 private:
  const nlohmann::json& json_;
  std::string what_;
  std::set<std::string> known_;
};

}  // namespace uw::sim
