// A GoogleTest fixture for readers of one text file (nav.csv,
// image_times.csv, generic CSV tables): Read(text) writes `text` to a fresh
// file and reads it back; Error(text) returns the reader's uw::Error
// message, or "no error".
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "common/util/error.h"
#include "tests/support/process.h"

namespace uw {

template <typename Result>
class TextFileReaderTest : public ::testing::Test {
 protected:
  using Reader = std::function<Result(const std::filesystem::path&)>;

  TextFileReaderTest(std::string suite, std::string file_name, Reader reader)
      : suite_(std::move(suite)),
        file_name_(std::move(file_name)),
        reader_(std::move(reader)) {}

  void SetUp() override { path_ = testing::FreshTestDir(suite_) / file_name_; }

  Result Read(const std::string& text) {
    std::ofstream(path_, std::ios::binary) << text;
    return reader_(path_);
  }

  std::string Error(const std::string& text) {
    try {
      Read(text);
    } catch (const uw::Error& error) {
      return error.what();
    }
    return "no error";
  }

  std::filesystem::path path_;

 private:
  std::string suite_;
  std::string file_name_;
  Reader reader_;
};

}  // namespace uw
