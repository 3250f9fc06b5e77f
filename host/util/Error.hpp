#pragma once
// User-facing errors. Anything the user can cause (bad file, bad flag, missing
// driver) is thrown as UserError; the CLI prints its one-line message and exits
// with code 2. Programming errors stay as std::logic_error and friends.
#include <stdexcept>
#include <string>

namespace ml {

class UserError : public std::runtime_error {
 public:
  explicit UserError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace ml
