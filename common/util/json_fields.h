// Reading and writing options structs and uwmetric files as JSON (uwsim's
// sim.json and --config, lasers.json, rig.json, spots.json, ...): the one
// strict reader. Every key read is known, anything else is an error naming
// it and the keys that are valid; a value of the wrong type is an error
// naming its path (`lasers.optics.waist_radius_m: expected a number, got
// "big"`).
//
// One way to convert each kind of thing:
//  - an options struct that is a section of an options file (sim.json's
//    world_options, survey_options, render, ...) has nlohmann's pair beside
//    it, `to_json(json&, const X&)` writing every field and `from_json(const
//    json&, X&)` reading through JsonFields, so that sections nest
//    (`{"render", config.render}`, `fields.Read("render", &config.render)`)
//    and a file may leave out what keeps its default; a struct that is only
//    ever a part of such a section (world options' relief, rocks) is read in
//    place with `fields.Section(...)`, so that its errors carry its parent's
//    path (`world options: vent.ground_relief`);
//  - anything else, a value inside a file (vectors, cameras, poses, lasers)
//    or a document that is only written (reports), has free functions:
//    `ToJson(x)` or `XJson(x)` returning the JSON and `XFromJson(json,
//    where)` reading it, as its reader needs to name where in its file the
//    value sits ("rig.cameras[1].camera"), which from_json cannot be told.
#pragma once

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "common/util/error.h"

namespace uw {

nlohmann::json ToJson(const Eigen::Vector3d& value);
// A 3x3 matrix as an array of its rows.
nlohmann::json ToJson(const Eigen::Matrix3d& value);
// An array of [x, y, z], as Read reads it back.
nlohmann::json ToJson(const std::vector<Eigen::Vector3d>& values);

// Parses a file's text; a syntax error or a number out of range (1e999)
// names `where` and the position.
nlohmann::json ParseJsonText(const std::string& text, const std::string& where);

// Reads the keys of one JSON object into the fields of an options struct:
//
//   JsonFields fields(json, "lasers");
//   fields.Read("every_nth_image", &options.every_nth_image);
//   fields.Section("optics", [&](JsonFields& optics) { ... });
//   fields.RejectUnknown();
//
// A key absent from the JSON leaves its field as it was (its default).
// Errors name `what`, the key and the offending value.
class JsonFields {
 public:
  // `what` names the object in messages ("lasers", "world options:
  // seafloor", "rig.json: cameras[1]"); throws unless `json` is an object.
  JsonFields(const nlohmann::json& json, std::string what);

  // Reads `key` if present (returns whether it was). Numbers must be
  // numbers, integers integers in the field's range, booleans booleans,
  // strings strings, vectors arrays of 3 numbers; any other type is read by
  // nlohmann::json's from_json (an options struct's own, for a section that
  // names its errors itself).
  bool Read(const std::string& key, double* value);
  bool Read(const std::string& key, bool* value);
  bool Read(const std::string& key, std::string* value);
  bool Read(const std::string& key, std::vector<double>* value);
  bool Read(const std::string& key, std::array<double, 3>* value);
  bool Read(const std::string& key, Eigen::Vector3d* value);
  // null unsets it.
  bool Read(const std::string& key, std::optional<Eigen::Vector3d>* value);
  // An array of [x, y, z]; replaces the whole vector.
  bool Read(const std::string& key, std::vector<Eigen::Vector3d>* value);
  // An array of 3 rows of 3 numbers.
  bool Read(const std::string& key, Eigen::Matrix3d* value);
  template <typename T>
  std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool>, bool>
  Read(const std::string& key, T* value);
  template <typename T>
  std::enable_if_t<!std::is_arithmetic_v<T>, bool> Read(const std::string& key,
                                                        T* value);

  // Like Read, for a key that must be present.
  template <typename T>
  void Require(const std::string& key, T* value) {
    if (!json_.contains(key)) {
      throw ErrorAt(what_, ": missing key \"", key, "\"");
    }
    Read(key, value);
  }

  // A nested object: if `key` is present, `read` gets its fields, named
  // `what.key` (or `name`), and then its unknown keys are rejected.
  template <typename ReadSection>
  bool Section(const std::string& key, ReadSection read) {
    return Section(key, what_ + "." + key, read);
  }
  template <typename ReadSection>
  bool Section(const std::string& key, const std::string& name,
               ReadSection read) {
    const nlohmann::json* item = Find(key);
    if (item == nullptr) return false;
    JsonFields section(*item, name);
    read(section);
    section.RejectUnknown();
    return true;
  }

  // A uwmetric file's "format" and "version": both required and ours.
  void RequireFormat(const std::string& format, int version);
  // The same for a reader of several versions: returns the one read.
  int RequireFormat(const std::string& format, int oldest_version,
                    int newest_version);

  // Called once every field is read: a key nothing asked for is a typo or a
  // parameter this version does not have.
  void RejectUnknown() const;

 private:
  // The value at `key`, or nullptr; `key` becomes a valid key.
  const nlohmann::json* Find(const std::string& key);
  [[noreturn]] void Fail(const std::string& key, const std::string& expected,
                         const nlohmann::json& value) const;
  Eigen::Vector3d Vector3(const nlohmann::json& value,
                          const std::string& key) const;

  const nlohmann::json& json_;
  std::string what_;
  // In the order they were asked for, as the error lists them.
  std::vector<std::string> known_;
};

template <typename T>
std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool>, bool>
JsonFields::Read(const std::string& key, T* value) {
  const nlohmann::json* item = Find(key);
  if (item == nullptr) return false;
  if (!item->is_number_integer()) Fail(key, "an integer", *item);
  // Compared as the magnitudes of the value and of T's range, whichever
  // of nlohmann's two integer types holds it.
  constexpr uint64_t kMax =
      static_cast<uint64_t>(std::numeric_limits<T>::max());
  bool fits = false;
  if (item->is_number_unsigned()) {
    fits = item->get<uint64_t>() <= kMax;
  } else {
    const int64_t wide = item->get<int64_t>();
    fits =
        wide >= 0
            ? static_cast<uint64_t>(wide) <= kMax
            : std::is_signed_v<T> &&
                  wide >= static_cast<int64_t>(std::numeric_limits<T>::min());
  }
  if (!fits) {
    Fail(key,
         std::is_same_v<T, int>
             ? std::string("an integer in the range of int")
             : "an integer in [" +
                   std::to_string(std::numeric_limits<T>::min()) + ", " +
                   std::to_string(std::numeric_limits<T>::max()) + "]",
         *item);
  }
  *value = item->get<T>();
  return true;
}

template <typename T>
std::enable_if_t<!std::is_arithmetic_v<T>, bool> JsonFields::Read(
    const std::string& key, T* value) {
  const nlohmann::json* item = Find(key);
  if (item == nullptr) return false;
  try {
    item->get_to(*value);
  } catch (const nlohmann::json::exception& error) {
    throw ErrorAt(what_, ".", key, ": ", error.what());
  }
  return true;
}

}  // namespace uw
