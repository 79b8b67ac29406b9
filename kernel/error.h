// The one exception type of wedge. Kernel functions throw wedge::Error on bad input with a
// message a person can act on: what was wrong, which argument, which value. The Lua layer
// turns it into a Lua error at the script's file and line. Nothing in wedge aborts on bad input.
#pragma once
#include <sstream>
#include <stdexcept>
#include <string>

namespace wedge {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// Builds a message from pieces and throws it: fail("radius must be positive, got ", r).
template <class... Parts>
[[noreturn]] void fail(const Parts&... parts) {
  std::ostringstream out;
  out.precision(17);
  (out << ... << parts);
  throw Error(out.str());
}

// Throws unless x is a finite number; `what` names the argument ("radius").
void require_finite(double x, const char* what);
// Throws unless x > 0 and finite.
void require_positive(double x, const char* what);

}  // namespace wedge
