// uw::Error — the one exception type our libraries throw.
//
// Libraries never print; they throw an Error whose message says what was
// wrong and where (file, line or byte offset, image name), so that a CLI can
// print it verbatim and exit non-zero.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace uw {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Builds "where: what" messages from stream-able pieces:
//   throw uw::ErrorAt(path, ":", line, ": expected 4 parameters, got ", n);
template <typename... Args>
Error ErrorAt(const Args&... args) {
  std::ostringstream message;
  (message << ... << args);
  return Error(message.str());
}

}  // namespace uw
