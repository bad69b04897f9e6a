// The error the implicit stepper throws when Newton fails for good (docs/model.md 1.10).
#pragma once

#include <stdexcept>

namespace flagella {

class SolverFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace flagella
