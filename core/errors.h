#pragma once

#include <stdexcept>

namespace nfrc {

// Bad user input: the message names the field ("nonlinearities[0].mu: ...") or the file.
// Thrown by readers and by the Validate() methods of typed specifications; every layer may
// throw it, only the edges (CLI, Python) turn it into an exit code or an exception.
class InputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace nfrc
