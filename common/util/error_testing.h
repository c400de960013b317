// For tests: that a call throws uw::Error with a message naming what was
// wrong (DESIGN.md: messages name the file, line or image).
#pragma once

#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "common/util/error.h"

namespace uw {

inline void ExpectErrorContaining(const std::function<void()>& body,
                                  const std::string& text) {
  try {
    body();
    ADD_FAILURE() << "no error; expected one containing '" << text << "'";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(text), std::string::npos)
        << error.what();
  }
}

// The message of the uw::Error that `body` throws; "" when it throws none.
inline std::string ErrorOf(const std::function<void()>& body) {
  try {
    body();
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

}  // namespace uw
