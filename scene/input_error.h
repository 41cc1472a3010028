// input_error.h — the one exception type for bad input. Its message always
// names the file (or built-in source) and where in it: a byte offset for
// binary files, line and column name for text tables, an element for meshes.
#pragma once
#include <stdexcept>
#include <string>

namespace ft {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ft
