// The one exception type for bad input: what() is one line naming the file and
// what is wrong, e.g. "scene.json: draws[2].state.cull: expected one of none,
// back, front". The command line prints it and exits with status 2.
#pragma once

#include <stdexcept>

namespace gpusim {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace gpusim
