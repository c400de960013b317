#include "common/util/json_fields.h"

#include <cstdint>
#include <functional>

#include <gtest/gtest.h>

#include "common/util/error_testing.h"

namespace uw {
namespace {

struct Sample {
  double ratio = 0.5;
  int count = 3;
  uint32_t id = 1;
  bool enabled = false;
  std::string name = "a";
  std::array<double, 3> albedo = {0.1, 0.2, 0.3};
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  std::optional<Eigen::Vector3d> target;
  std::vector<Eigen::Vector3d> biases;
  std::vector<double> params;
  double inner_size = 1.0;
};

void ReadSample(const nlohmann::json& json, Sample* sample) {
  JsonFields fields(json, "sample");
  fields.Read("ratio", &sample->ratio);
  fields.Read("count", &sample->count);
  fields.Read("id", &sample->id);
  fields.Read("enabled", &sample->enabled);
  fields.Read("name", &sample->name);
  fields.Read("albedo", &sample->albedo);
  fields.Read("offset", &sample->offset);
  fields.Read("target", &sample->target);
  fields.Read("biases", &sample->biases);
  fields.Read("params", &sample->params);
  fields.Section("inner", [&](JsonFields& inner) {
    inner.Read("size", &sample->inner_size);
  });
  fields.RejectUnknown();
}

std::string ErrorOf(const std::string& text) {
  try {
    Sample sample;
    ReadSample(nlohmann::json::parse(text), &sample);
  } catch (const Error& error) {
    return error.what();
  }
  return "(no uw::Error)";
}

TEST(JsonFields, ReadsPresentKeysAndKeepsTheOthers) {
  Sample sample;
  ReadSample(nlohmann::json::parse(R"({
      "ratio": 2, "count": -4, "id": 7, "enabled": true, "name": "b",
      "albedo": [1, 2, 3], "offset": [0.5, 0, -1], "target": [1, 2, 3],
      "biases": [[1, 0, 0], [0, 2, 0]], "params": [4, 5.5],
      "inner": {"size": 9}})"),
             &sample);
  EXPECT_EQ(sample.ratio, 2.0);
  EXPECT_EQ(sample.count, -4);
  EXPECT_EQ(sample.id, 7u);
  EXPECT_TRUE(sample.enabled);
  EXPECT_EQ(sample.name, "b");
  EXPECT_EQ(sample.albedo[2], 3.0);
  EXPECT_EQ(sample.offset, Eigen::Vector3d(0.5, 0, -1));
  ASSERT_TRUE(sample.target.has_value());
  EXPECT_EQ(*sample.target, Eigen::Vector3d(1, 2, 3));
  ASSERT_EQ(sample.biases.size(), 2u);
  EXPECT_EQ(sample.biases[1], Eigen::Vector3d(0, 2, 0));
  EXPECT_EQ(sample.params, (std::vector<double>{4, 5.5}));
  EXPECT_EQ(sample.inner_size, 9.0);

  Sample defaults;
  defaults.target = Eigen::Vector3d(1, 1, 1);
  ReadSample(nlohmann::json::parse(R"({"target": null})"), &defaults);
  EXPECT_FALSE(defaults.target.has_value());
  EXPECT_EQ(defaults.count, 3);
  EXPECT_EQ(defaults.name, "a");
}

TEST(JsonFields, ReadReportsWhetherTheKeyWasThere) {
  const nlohmann::json json = {{"a", 1.5}};
  JsonFields fields(json, "x");
  double a = 0.0, b = 0.0;
  EXPECT_TRUE(fields.Read("a", &a));
  EXPECT_FALSE(fields.Read("b", &b));
  EXPECT_EQ(a, 1.5);
  EXPECT_EQ(b, 0.0);
}

TEST(JsonFields, WrongTypesAndUnknownKeysNameThePathAndTheValue) {
  const struct {
    const char* json;
    const char* message;
  } cases[] = {
      {R"({"ratio": "big"})", "sample.ratio: expected a number, got \"big\""},
      {R"({"ratio": true})", "sample.ratio: expected a number, got true"},
      {R"({"count": 2.5})", "sample.count: expected an integer, got 2.5"},
      {R"({"count": 3000000000})",
       "sample.count: expected an integer in the range of int, got "
       "3000000000"},
      {R"({"id": -1})",
       "sample.id: expected an integer in [0, 4294967295], got -1"},
      {R"({"enabled": 1})", "sample.enabled: expected true or false, got 1"},
      {R"({"name": 3})", "sample.name: expected a string, got 3"},
      {R"({"albedo": [1, 2]})",
       "sample.albedo: expected an array of 3 numbers, got [1,2]"},
      {R"({"offset": [1, "2", 3]})",
       "sample.offset: expected an array of 3 numbers"},
      {R"({"target": 1})", "sample.target: expected an array of 3 numbers"},
      {R"({"biases": [1, 2, 3]})",
       "sample.biases: expected an array of 3 numbers, got 1"},
      {R"({"biases": {}})", "sample.biases: expected an array of [x, y, z]"},
      {R"({"params": [1, null]})",
       "sample.params: expected an array of numbers, got [1,null]"},
      {R"({"inner": 3})", "sample.inner: expected a JSON object, got 3"},
      {R"({"inner": {"size": "s"}})", "sample.inner.size: expected a number"},
      {R"({"inner": {"sise": 1}})",
       "sample.inner: unknown key \"sise\" (valid: size)"},
      {R"({"ratoi": 1})",
       "sample: unknown key \"ratoi\" (valid: ratio, count, id, enabled, "
       "name, albedo, offset, target, biases, params, inner)"},
      {"[]", "sample: expected a JSON object, got []"},
  };
  for (const auto& test : cases) {
    EXPECT_EQ(ErrorOf(test.json).substr(0, std::string(test.message).size()),
              test.message)
        << test.json;
  }
}

TEST(JsonFields, SectionsMayBeNamedByTheirReader) {
  const nlohmann::json json = nlohmann::json::parse(R"({"a": {"b": "x"}})");
  JsonFields fields(json, "options");
  double b = 0.0;
  ExpectErrorContaining(
      [&] {
        fields.Section("a", "options: a",
                       [&](JsonFields& a) { a.Read("b", &b); });
      },
      "options: a.b: expected a number, got \"x\"");
}

TEST(JsonFields, RequireAndFormat) {
  const nlohmann::json json = {{"format", "uwmetric-x"}, {"version", 2}};
  JsonFields fields(json, "x.json");
  ExpectErrorContaining([&] { fields.RequireFormat("uwmetric-x", 1); },
                        "x.json: expected format \"uwmetric-x\" version 1, got "
                        "\"uwmetric-x\" version 2");
  double missing = 0.0;
  ExpectErrorContaining([&] { fields.Require("scale", &missing); },
                        "x.json: missing key \"scale\"");
}

TEST(JsonFields, OtherTypesUseTheirFromJson) {
  const nlohmann::json json = {{"list", {"a", "b"}}, {"bad", 3}};
  JsonFields fields(json, "x");
  std::vector<std::string> list;
  EXPECT_TRUE(fields.Read("list", &list));
  EXPECT_EQ(list, (std::vector<std::string>{"a", "b"}));
  std::vector<std::string> bad;
  ExpectErrorContaining([&] { fields.Read("bad", &bad); }, "x.bad: ");
}

TEST(JsonFields, VectorListsWrittenByToJsonReadBack) {
  const std::vector<Eigen::Vector3d> biases = {{1, 0, 0.25}, {0, -2, 0}};
  const nlohmann::json json = {{"biases", ToJson(biases)}};
  EXPECT_EQ(json.dump(), R"({"biases":[[1.0,0.0,0.25],[0.0,-2.0,0.0]]})");
  Sample sample;
  ReadSample(json, &sample);
  EXPECT_EQ(sample.biases, biases);
  EXPECT_EQ(ToJson(std::vector<Eigen::Vector3d>()), nlohmann::json::array());
}

}  // namespace
}  // namespace uw
