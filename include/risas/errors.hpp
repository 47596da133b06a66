// The one exception type for bad input: frames, intrinsics, files, parameters
// that cannot be processed. Its message says what is wrong in user terms.
#pragma once

#include <stdexcept>
#include <string>

namespace risas {

class InputError : public std::invalid_argument {
 public:
  explicit InputError(const std::string& what) : std::invalid_argument(what) {}
};

}  // namespace risas
